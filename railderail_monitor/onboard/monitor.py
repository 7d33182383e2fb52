"""The on-board monitor as a stream: `MeasuredMonitor`, fed the sensors' samples as they arrive (each unit's
in stamp order, the units interleaved in any order), raises the same alerts, at the same samples, as
`measured.evaluate` + `measured.alerts` over the whole record.

How it can: every criterion's value is a processor that gives the same numbers whatever the chunks it is fed
(onboard.criteria: filters with their state carried, the trailing windows, the peak counts, the odometer;
estimator.RollBalance, the twist), and a stamp is decided only once nothing that arrives later can change it. A unit's
samples are complete up to its watermark, its last stamp plus its sample period less the stamps' jitter
(`measured.sample_rates`, STAMP_JITTER: the next stamp comes about a period later, or later still if samples
are lost); a channel's sample is processed once
the odometer is complete up to its stamp (its track position is then final); a criterion's stamp once each of
its channels' units and the odometer are complete up to it; the estimator's once all its inputs are. So the
latency is the arrival of the same instant's samples of the other units, not a sample period. `finish()` ends
every stream (the rest of the record is decided). A unit whose stamps jitter by more than that can make a
stamp decided before a sample at or before it arrives: then stream and batch differ (the simulator's and a
logger's stamps on a fixed clock do not).

Each channel has the monitor's Detector (warning.alarms.Detector: debounce, re-arm), fed the criterion's value and
the odometer's position at each stamp, as `measured.alerts` runs `warning.alarms.alarm_intervals`.
"""
from __future__ import annotations

import math

import numpy as np

from railderail_sim.ranges import check_range
from railderail_sim.sensors.sensor_set import ODOMETER

from ..warning.limits import SEVERITY_WARNING
from ..warning.alarms import Detector
from . import criteria as oc
from . import measured as me

PRUNE_EVERY = 64        # feeds between dropping the samples no stamp still to be decided needs
# s: how much earlier than a period after the previous one a unit's stamp may come. A logger's clock and the
# simulator's stamp each sample on a fixed grid; 1 ms is a USB or CAN bus's time-stamping spread (A)
STAMP_JITTER = 0.001


class _Input:
    """A sensor unit's samples as they arrive, kept while a consumer needs them (in arrays grown by
    doubling: a sample's arrival is a copy into them)."""

    def __init__(self, unit, rate_hz, jitter_s):
        # how far past its last stamp no sample can be: a period, less the stamps' jitter (at most half of it)
        self.unit, self.ahead = unit, max(1.0 / rate_hz - jitter_s, 0.5 / rate_hz)
        self._t, self._signals, self.begin, self.end = np.zeros(64), {}, 0, 0
        self.first = self.last = -math.inf
        self.closed = False

    @property
    def t(self):
        return self._t[self.begin:self.end]

    @property
    def signals(self):
        return {name: values[self.begin:self.end] for name, values in self._signals.items()}

    def add(self, time, signals):
        if isinstance(time, float) and time > self.last:            # one sample: fewer array calls
            if self.end + 1 > len(self._t):
                self._grow(1)
            if self.first == -math.inf:
                self.first = time
            self._t[self.end] = time
            for name, values in signals.items():
                if name not in self._signals:
                    self._signals[name] = np.zeros((len(self._t),) + np.shape(values))
                self._signals[name][self.end] = values
            self.end += 1
            self.last = time
            return
        t = np.atleast_1d(np.asarray(time, dtype=float))
        n = len(t)
        if not n:
            return
        if not (t[0] > self.last and (n == 1 or np.all(np.diff(t) > 0))):
            raise ValueError(f"{self.unit}: stamp {t[0]:.9f} s is not after its last {self.last:.9f} s: each "
                             "unit's samples must come in strictly increasing stamp order")
        if self.first == -math.inf:
            self.first = float(t[0])
        if self.end + n > len(self._t):
            self._grow(n)
        self._t[self.end:self.end + n] = t
        for name, values in signals.items():
            values = np.asarray(values, dtype=float).reshape((n,) + np.shape(values)[np.ndim(time):])
            if name not in self._signals:
                self._signals[name] = np.zeros((len(self._t),) + values.shape[1:])
            self._signals[name][self.end:self.end + n] = values
        self.end += n
        self.last = float(t[-1])

    def _grow(self, n):
        """Move the kept samples to the start, in arrays large enough for n more."""
        kept = self.end - self.begin
        size = max(64, 2 * (kept + n))
        t = np.zeros(size)
        t[:kept] = self._t[self.begin:self.end]
        for name, values in self._signals.items():
            grown = np.zeros((size,) + values.shape[1:])
            grown[:kept] = values[self.begin:self.end]
            self._signals[name] = grown
        self._t, self.begin, self.end = t, 0, kept

    @property
    def started(self):
        return self.first > -math.inf

    @property
    def watermark(self):
        """Every sample at or before a stamp below this has arrived."""
        return math.inf if self.closed else self.last + self.ahead

    def after(self, done, bound):
        """The slice of the kept samples with stamps in (done, bound)."""
        t = self.t
        return slice(int(t.searchsorted(done, "right")), int(t.searchsorted(bound, "left")))

    def rows(self, cut):
        """{signal: its values} of a slice of the kept samples."""
        a, b = self.begin + cut.start, self.begin + cut.stop
        return {name: values[a:b] for name, values in self._signals.items()}

    def forget(self, before):
        """Drop all but the last sample at or before `before` and those after it."""
        self.begin += max(int(self.t.searchsorted(before, "right")) - 1, 0)


class _Channel:
    """A criterion's value at one unit's samples (its processor fed in stamp order)."""

    def __init__(self, unit, read, processor):
        self.unit, self.read, self.processor = unit, read, processor
        self.done = -math.inf
        self.t, self.v = np.zeros(0), None

    def advance(self, source: _Input, odometer: oc.Odometer, odometer_watermark):
        cut = source.after(self.done, odometer_watermark)
        if cut.start >= cut.stop:
            return
        t = source.t[cut]
        v = self.processor(self.read(source.rows(cut)), odometer.position(t))
        self.t = np.concatenate([self.t, t])
        self.v = v if self.v is None else np.concatenate([self.v, v])
        self.done = float(t[-1])

    def held(self, stamps):
        return me.held(self.t, self.v, stamps) if self.v is not None else np.full(len(stamps), np.nan)

    def forget(self, before):
        keep = max(int(np.searchsorted(self.t, before, "right")) - 1, 0)
        self.t, self.v = self.t[keep:], (self.v[keep:] if self.v is not None else None)


class _Alarms:
    """The Detectors of a criterion's channels and the count of its time base's stamps so far."""

    def __init__(self, criterion, limits: me.MeasuredLimits):
        self.criterion, self.places = criterion, me.PLACES[criterion]
        self.detectors = [[Detector(level, limits.debounce(criterion), limits.rearm_fraction, limits.rearm_m)
                           for _ in self.places] for _, level in limits.levels(criterion)]
        self.samples = 0

    def update(self, stamps, values, positions):
        """Alerts of the stamps (n,) with their values (n, places) and positions (n,)."""
        found = []
        for i in range(len(stamps)):
            for detectors in self.detectors:
                for k, detector in enumerate(detectors):
                    value = float(values[i, k])
                    if detector.update(value, float(positions[i])):
                        found.append(me.MeasuredAlert(float(stamps[i]), self.samples + i, self.criterion,
                                                      SEVERITY_WARNING, value, detector.threshold, self.places[k],
                                                      float(positions[i])))
        self.samples += len(stamps)
        return found


class _Criterion:
    """A criterion on measured signals: its channels merged on their stamps, its alarms."""

    def __init__(self, criterion, limits, vehicle, rates):
        read, processor = me.CHANNELS[criterion]
        self.units = me.PLACES[criterion]
        self.channels = [_Channel(u, read, processor(limits, vehicle, rates[u])) for u in self.units]
        self.alarms = _Alarms(criterion, limits)
        self.done = -math.inf

    def advance(self, inputs, odometer, odometer_watermark, unit=None):
        """`unit`: the one unit that got samples since the last call (None: any, or the odometer)."""
        for ch in self.channels:
            if unit is None or ch.unit == unit:
                ch.advance(inputs[ch.unit], odometer, odometer_watermark)
        bound = min([inputs[u].watermark for u in self.units] + [odometer_watermark])
        if not any(ch.t.size and ch.t[-1] > self.done for ch in self.channels) or not bound > self.done:
            return []
        one = {ch.t[-1] if ch.t.size and ch.t[-1] > self.done and (ch.t.size < 2 or ch.t[-2] <= self.done) else None
               for ch in self.channels}
        if len(one) == 1 and None not in one and min(one) < bound:
            # the usual case, a stamp that every channel has (the same as the general case, without its calls)
            stamps = np.array([min(one)])
            values = np.array([[ch.v[-1] for ch in self.channels]])
        else:
            stamps = np.unique(np.concatenate([ch.t[(ch.t > self.done) & (ch.t < bound)] for ch in self.channels]))
            if not len(stamps):
                return []
            values = np.stack([ch.held(stamps) for ch in self.channels], axis=1)
        self.done = float(stamps[-1])
        for ch in self.channels:
            ch.forget(self.done)
        return self.alarms.update(stamps, values, odometer.position(stamps))

    def progress(self, unit):
        return min(ch.done for ch in self.channels if ch.unit == unit)


class _Group:
    """A criterion group (measured.Group: the estimator, the twist) at its time base's stamps from the first at
    which every input has a sample; `on_values(stamps, values)` gets each batch of decided stamps (the
    group processor's dict), if given."""

    def __init__(self, group: me.Group, limits, vehicle, rates, wind=None, on_values=None):
        self.group, self.processor = group, group.make(limits, vehicle, rates, wind)
        self.units = group.units
        self.alarms = [_Alarms(c, limits) for c in group.criteria]
        self.done, self.start = -math.inf, None
        self.on_values = on_values

    def advance(self, inputs, odometer, odometer_watermark, unit=None):
        if self.start is None:
            if not all(inputs[u].started for u in self.units):
                return []
            self.start = max(inputs[u].first for u in self.group.inputs)
            self.sources = [inputs[u] for u in self.units]
            self.slowest = None
        start = self.start
        base = inputs[self.group.base]
        if not base.last > self.done:
            return []
        # the inputs' watermark only moves when the slowest one's does
        if self.slowest is None or self.slowest.watermark != self.slowest_mark:
            self.slowest = min(self.sources, key=lambda source: source.watermark)
            self.slowest_mark = self.slowest.watermark
        bound = min(self.slowest_mark, odometer_watermark)
        if not base.last > self.done or not bound > self.done:
            return []
        stamps = base.t[base.after(max(self.done, np.nextafter(start, -math.inf)), bound)]
        if not len(stamps):
            return []
        arrays = {f"sensor_{u}_{name}": values for u in self.units for name, values in inputs[u].signals.items()}
        arrays.update({f"sensor_{u}_time": inputs[u].t for u in self.units})
        values = self.processor(arrays, stamps, odometer)
        self.done = float(stamps[-1])
        if self.on_values is not None:
            self.on_values(stamps, values)
        positions = odometer.position(stamps)
        return sum((a.update(stamps, values[key], positions) for a, key in zip(self.alarms, self.group.criteria.values())),
                   [])


class MeasuredMonitor:
    """Every criterion on measured signals over sensor samples fed as they arrive (`feed`), its alerts
    (measured.MeasuredAlert) as soon as they are decided; `finish()` at the end of the record.

    `rates`: {unit: Hz} of the sensor set (`measured.sample_rates`, default the shipped set's): the units
    fed, and the criteria run (those whose units, and the odometer, are all there). `jitter_s`: how much
    earlier than a period after its previous one a unit's stamp may come (at most half a period is used).
    `on_estimate(stamps, estimates)`: called with the estimator's values (estimator.RollBalance's dict) at
    each batch of stamps it decides, in stamp order (the node publishes them). `wind`: an
    estimator.GivenWind the estimator takes into account (measured.evaluate's)."""

    def __init__(self, vehicle, limits: me.MeasuredLimits = None, rates=None, jitter_s=STAMP_JITTER,
                 on_estimate=None, wind=None):
        self.limits = (limits or me.measured_limits(vehicle)).validated()
        rates = me.sample_rates() if rates is None else dict(rates)
        check_range("stamp jitter", jitter_s, 0.0, 1.0, "s")
        self.inputs = {u: _Input(u, r, jitter_s) for u, r in rates.items()}
        found = me.criteria_of(self.inputs)
        self.left_out = me.left_out(self.inputs)       # ({criterion: missing units}, the sentence): the node logs it
        self.criteria = [_Criterion(c, self.limits, vehicle, rates) for c in found if c in me.CHANNELS]
        self.groups = [_Group(g, self.limits, vehicle, rates, wind, on_estimate if g is me.GROUPS[0] else None)
                       for g in me.GROUPS if any(c in g.criteria for c in found)]
        self.odometer = oc.Odometer()
        self.feeds = self.pruned = 0
        self.all = self.criteria + self.groups
        self.waiting = set()        # the consumers with samples added since the last advance (None: all)
        # the consumers each unit's samples may advance (the odometer's: all)
        self.consumers = {u: [c for c in self.all if u in c.units] for u in self.inputs}

    def feed(self, unit, time, **signals):
        """A unit's sample (time a float, each signal its values) or samples (time (n,), signals (n, ...)):
        `acceleration` and `angular_rate` of a mount, `deflection` and `pressure` of the air springs, `speed`
        of the odometer (the names of `sensor_<unit>_<signal>`). Returns the alerts now decided."""
        self.add(unit, time, **signals)
        return self.advance()

    def add(self, unit, time, **signals):
        """`feed` without deciding anything yet (`advance` decides): several units' samples that came
        together are then processed together, each consumer once."""
        if unit not in self.inputs:
            raise ValueError(f"unknown sensor unit {unit!r}: the monitor's units are {', '.join(self.inputs)}")
        self.inputs[unit].add(time, signals)
        if unit == ODOMETER:
            self.odometer.add(np.atleast_1d(time), np.atleast_1d(signals["speed"]))
            self.waiting = None
        elif self.waiting is not None:
            self.waiting.add(unit)
        self.feeds += 1

    def advance(self):
        """The alerts decided by the samples added since the last call."""
        waiting = self.waiting
        unit = next(iter(waiting)) if waiting is not None and len(waiting) == 1 else None
        if waiting is None:
            consumers = None
        else:
            chosen = self.consumers_of(waiting)
            consumers = [c for c in self.all if c in chosen]
        found = self._advance(consumers, unit)
        self.waiting = set()
        if self.feeds - self.pruned >= PRUNE_EVERY:
            self._forget()
            self.pruned = self.feeds
        return found

    def finish(self):
        """The end of every stream: the alerts of what is left."""
        for source in self.inputs.values():
            source.closed = True
        self.waiting = None
        return self.advance()

    def consumers_of(self, units):
        return {c for u in units for c in self.consumers[u]}

    def _advance(self, consumers=None, unit=None):
        """Advance the consumers (default all) as far as the watermarks let them; `unit`: the one unit that
        got samples, if only one did."""
        if ODOMETER not in self.inputs:
            return []
        if consumers is None:
            consumers = self.all
        watermark = self.inputs[ODOMETER].watermark
        found = []
        for c in consumers:
            found += c.advance(self.inputs, self.odometer, watermark, unit)
        if not found:
            return found
        return sorted(found, key=lambda a: (a.time_s, me.CRITERIA.index(a.criterion),
                                            me.PLACES[a.criterion].index(a.place)))

    def _forget(self):
        """Drop the samples no stamp still to be decided needs."""
        oldest = math.inf
        for unit, source in self.inputs.items():
            needed = [c.progress(unit) for c in self.criteria if unit in c.units]
            needed += [g.done for g in self.groups if unit in g.units]
            if unit != ODOMETER:
                before = min(needed, default=source.last)
                source.forget(before)
                oldest = min(oldest, before, *[c.done for c in self.criteria])
        self.odometer.forget(oldest)
        self.inputs[ODOMETER].forget(oldest)
