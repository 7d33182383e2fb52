"""The sensor models: each kind of instrument the sensor set uses, every value with its unit, source and how
sure (parameters.py's style: V verified in the source, S a documented value of a similar device or a range
the source gives, A our assumption or derivation; the source's own grading of the reference sheet, A/B/C,
is quoted in SOURCES).

The shipped instruments have no scale-factor error (`scale_factor_error` 0) and the shipped mounts no
misalignment, so that the shipped set's signals stay what the warning catalogue was scored on; `REALISTIC`
holds the sourced values of both, which config.realistic_set puts on (config/sensors-realistic.yaml).

An instrument measures one quantity on three axes (accelerometers, gyros) or one (air-spring pressure and
height). Its model, applied by `measure` to the ideal signal at the simulator's output rate, in this order:
the constant bias (drawn once per axis from the seed, 1-sigma `bias`) and its random walk
(`bias_random_walk` per square root of a second) and white noise of `noise_density` are added; the
sensing element saturates at [range_low, range_high]; an AC coupling (first-order high-pass at
`high_pass_hz`, IEPE sensors) and the anti-alias low-pass (Butterworth of `anti_alias_order` at
`anti_alias_ratio` times the mount's sample rate) filter it; it is sampled at the mount's rate, clipped to
the range again (the filter's overshoot) and quantised to `bits` over that range. The mount adds
its latency and drops samples (sensor_set.Mount).
"""
from dataclasses import dataclass, fields, replace
import math

from ..parameters import GRAVITY, parameter, parameter_rows
from ..ranges import check_range

G = GRAVITY
MICRO_G = 1.0e-6 * GRAVITY
DEG = math.pi / 180.0

SOURCES = {
    "ADXL355": "Analog Devices ADXL354/ADXL355 data sheet: +-2/4/8 g, 20-bit output, noise density 22.5 ug/sqrt(Hz) "
               "(B: the data sheet's value as quoted by ADI), 0 g offset vs temperature 0.15 mg/degC max, output "
               "data rates 3.906-4000 Hz with the digital low-pass at ODR/4 (A); as read in "
               "../shared/reference/onboard-and-assessment.md, 1.2",
    "ADXL357": "Analog Devices ADXL356/ADXL357 data sheet, Rev. A (2020): +-10/20/40 g, 20-bit, noise density "
               "75 ug/sqrt(Hz), 0 g offset vs temperature 0.75 mg/degC max (A); onboard-and-assessment.md, 1.2",
    "IEPE": "IEPE (piezoelectric) axle-box accelerometers: +-50...+-500 g, about 0.5 Hz to 10 kHz (+-3 dB), "
            "10-100 mV/g, EN 61373 category 3; typical values, not one data sheet (C); onboard-and-assessment.md, 1.3",
    "ADIS16470": "industrial MEMS gyro of the ADIS16470 class: rate noise density 0.005-0.01 deg/s/sqrt(Hz), in-run "
                 "bias stability 2-10 deg/h (the minimum of the Allan deviation, A: ADI's definition), range "
                 "+-125...+-2000 deg/s (C, recalled, not verified); onboard-and-assessment.md, 1.3",
    "pressure": "piezoresistive pressure transducer of the air springs, about 0-1 MPa (C); "
                "onboard-and-assessment.md, 1.1",
    "sensitivity": "ADXL356/ADXL357 data sheet Rev. A, Table 1: sensitivity at +-10 g 47 104 / 51 200 / 55 296 "
                   "LSB/g min/typ/max, +-8 % part to part (B: the table as quoted by ADI's support forum); the "
                   "ADXL355's +-2 g 235 520 / 256 000 / 276 480 LSB/g, the same +-8 % (C, recalled); sensitivity "
                   "change with temperature +-0.01 %/degC (the ADXL3xx family, C)",
    "IEPE calibration": "an IEPE sensor's calibration certificate gives its own sensitivity; the certificate's "
                        "uncertainty about 2 % (k = 2) is typical of back-to-back calibration (C, recalled)",
    "ADIS16470 calibration": "ADIS16470 data sheet: factory calibrated sensitivity, bias and axial alignment (B: "
                             "its first page as several copies show it); its sensitivity tolerance +-0.5 % "
                             "(C, recalled, not read in the table)",
    "model": "modelling choice or derivation of this project, explained in docs/onboard.md",
}


@dataclass(frozen=True)
class Instrument:
    """The model of one instrument (every axis alike); SI units of its quantity (`unit`)."""
    name: str
    quantity: str                   # acceleration, angular_rate, deflection or pressure
    unit: str
    noise_density: float = parameter(0.0, "unit/sqrt(Hz)", "model", "A", "white noise, one-sided")
    bias: float = parameter(0.0, "unit", "model", "A", "1-sigma of the constant bias of each axis, drawn from the seed")
    bias_random_walk: float = parameter(0.0, "unit/sqrt(s)", "model", "A", "the bias's random walk")
    range_low: float = parameter(-math.inf, "unit", "model", "A", "the reading clips here")
    range_high: float = parameter(math.inf, "unit", "model", "A", "and here")
    bits: int = parameter(0, "-", "model", "A", "quantisation over the range; 0: none")
    anti_alias_ratio: float = parameter(0.25, "-", "model", "A",
                                        "the anti-alias low-pass's corner over the sample rate")
    anti_alias_order: int = parameter(4, "-", "model", "A", "order of that Butterworth low-pass")
    high_pass_hz: float = parameter(0.0, "Hz", "model", "A", "corner of a first-order AC coupling; 0: DC response")
    scale_factor_error: float = parameter(0.0, "-", "model", "A", "1-sigma of each axis's relative sensitivity "
                                          "error, drawn from the seed; 0: the nominal sensitivity")

    @property
    def resolution(self):
        """The least significant bit (unit; 0 without quantisation)."""
        return (self.range_high - self.range_low) / 2.0 ** self.bits if self.bits else 0.0

    def validated(self):
        """self if every value is in its accepted range, else ValueError naming it."""
        where = f"instrument {self.name}"
        for name, unit in (("noise_density", "/sqrt(Hz)"), ("bias", ""), ("bias_random_walk", "/sqrt(s)")):
            check_range(f"{where} {name}", getattr(self, name), 0.0, 1.0e9, self.unit + unit)
        if not self.range_low < self.range_high:
            raise ValueError(f"{where}: range_low {self.range_low:g} must be below range_high {self.range_high:g} "
                             f"{self.unit}")
        check_range(f"{where} bits", self.bits, 0, 32)
        if self.bits and not math.isfinite(self.range_high - self.range_low):
            raise ValueError(f"{where}: bits {self.bits} need a finite range, not [{self.range_low:g}, "
                             f"{self.range_high:g}] {self.unit}")
        check_range(f"{where} anti_alias_ratio", self.anti_alias_ratio, 0.0, 0.5, lo_open=True, hi_open=True)
        check_range(f"{where} anti_alias_order", self.anti_alias_order, 1, 8)
        check_range(f"{where} high_pass_hz", self.high_pass_hz, 0.0, 10.0, "Hz")
        check_range(f"{where} scale_factor_error", self.scale_factor_error, 0.0, 0.5)
        return self

    def describe(self):
        """Rows (name, value, unit, source, sure, note) for reports (the unit of the quantity filled in)."""
        return [(f"{self.name}.{n}", v, u.replace("unit", self.unit), src, sure, note)
                for n, v, u, src, sure, note in parameter_rows(self)]


def _instrument(name, quantity, unit, **values):
    """(the Instrument, {field: (source, sure, note)}) of fields given as name=(value, source, sure, note)."""
    return (Instrument(name=name, quantity=quantity, unit=unit, **{k: v[0] for k, v in values.items()}),
            {k: v[1:] for k, v in values.items()})


# The shipped instruments, each value with where it comes from (source key, how sure, note).
_SHIPPED = {
    "adxl355": _instrument(
        "adxl355", "acceleration", "m/s^2",
        noise_density=(22.5 * MICRO_G, "ADXL355", "S", "22.5 ug/sqrt(Hz), the reference sheet's B"),
        bias=(1.5e-3 * G, "ADXL355", "A", "0.15 mg/degC max over an uncompensated 10 degC: derived"),
        bias_random_walk=(0.1e-3 * G / math.sqrt(3600.0), "model", "A",
                          "0.1 mg of drift in an hour; no data sheet value found"),
        range_low=(-2.0 * G, "ADXL355", "V", "+-2 g: the car body's accelerations with gravity"),
        range_high=(2.0 * G, "ADXL355", "V", ""),
        bits=(20, "ADXL355", "V", "3.9 ug per LSB at +-2 g"),
        anti_alias_ratio=(0.25, "ADXL355", "S", "the digital low-pass at ODR/4"),
        anti_alias_order=(4, "model", "A", "the data sheet's filter is not Butterworth; same bandwidth")),
    "adxl357": _instrument(
        "adxl357", "acceleration", "m/s^2",
        noise_density=(75.0 * MICRO_G, "ADXL357", "V", "Rev. A (Rev. 0: 80 ug/sqrt(Hz))"),
        bias=(7.5e-3 * G, "ADXL357", "A", "0.75 mg/degC max over an uncompensated 10 degC: derived"),
        bias_random_walk=(0.5e-3 * G / math.sqrt(3600.0), "model", "A",
                          "0.5 mg of drift in an hour; no data sheet value found"),
        range_low=(-10.0 * G, "ADXL357", "V", "+-10 g: a hunting bogie frame reads up to about 2 g"),
        range_high=(10.0 * G, "ADXL357", "V", ""),
        bits=(20, "ADXL357", "V", "19.5 ug per LSB at +-10 g"),
        anti_alias_ratio=(0.25, "ADXL355", "S", "the family's digital low-pass at ODR/4"),
        anti_alias_order=(4, "model", "A", "")),
    "iepe_axle_box": _instrument(
        "iepe_axle_box", "acceleration", "m/s^2",
        noise_density=(5.0 * MICRO_G, "model", "A",
                       "0.5 mg r.m.s. over 1 Hz-10 kHz, typical of a 100 mV/g general-purpose IEPE sensor; "
                       "not read in a data sheet"),
        range_low=(-50.0 * G, "IEPE", "S", "+-50 g, the low end of the typical ranges"),
        range_high=(50.0 * G, "IEPE", "S", ""),
        bits=(24, "model", "A", "the acquisition unit's 24-bit converter over the sensor's range"),
        anti_alias_ratio=(0.4, "model", "A", "a data-acquisition anti-alias filter at 0.4 of its sample rate"),
        anti_alias_order=(4, "model", "A", ""),
        high_pass_hz=(0.5, "IEPE", "S", "the lower -3 dB frequency: an IEPE sensor does not see gravity or a "
                                        "steady curving acceleration")),
    "adis16470": _instrument(
        "adis16470", "angular_rate", "rad/s",
        noise_density=(0.007 * DEG, "ADIS16470", "S", "0.007 deg/s/sqrt(Hz), inside the sheet's 0.005-0.01"),
        bias=(8.0 * DEG / 3600.0, "ADIS16470", "A",
              "the in-run bias stability 8 deg/h (inside 2-10 deg/h) as what stays after zeroing at a stop"),
        bias_random_walk=(8.0 * DEG / 3600.0 * math.sqrt(3.0 / 100.0), "model", "A",
                          "the random walk whose Allan deviation K sqrt(tau/3) reaches that stability at 100 s"),
        range_low=(-2000.0 * DEG, "ADIS16470", "S", "+-2000 deg/s"),
        range_high=(2000.0 * DEG, "ADIS16470", "S", ""),
        bits=(32, "ADIS16470", "S", "the 32-bit output registers (16-bit: 0.1 deg/s per LSB)"),
        anti_alias_ratio=(0.25, "model", "A", "its decimation filter taken like the accelerometers'"),
        anti_alias_order=(2, "model", "A", "")),
    "air_spring_pressure": _instrument(
        "air_spring_pressure", "pressure", "Pa",
        noise_density=(100.0, "model", "A", "100 Pa/sqrt(Hz): 0.03 % of full scale r.m.s. in 10 Hz"),
        bias=(2500.0, "model", "A", "0.25 % of full scale, a typical accuracy class"),
        range_low=(0.0, "pressure", "S", "gauge pressure 0-1 MPa"),
        range_high=(1.0e6, "pressure", "S", ""),
        bits=(16, "model", "A", "15 Pa per LSB"),
        anti_alias_ratio=(0.25, "model", "A", ""),
        anti_alias_order=(2, "model", "A", "")),
    "air_spring_height": _instrument(
        "air_spring_height", "deflection", "m",
        noise_density=(1.0e-5, "model", "A", "10 um/sqrt(Hz): 32 um r.m.s. in 10 Hz"),
        bias=(0.5e-3, "model", "A", "0.5 mm of mounting and calibration offset"),
        range_low=(-0.1, "model", "A", "+-100 mm: beyond both travel stops (35 mm down, 50 mm up)"),
        range_high=(0.1, "model", "A", ""),
        bits=(12, "model", "A", "49 um per LSB"),
        anti_alias_ratio=(0.25, "model", "A", ""),
        anti_alias_order=(2, "model", "A", "")),
}
INSTRUMENTS = {name: inst for name, (inst, _) in _SHIPPED.items()}
INSTRUMENT_SOURCES = {name: sources for name, (_, sources) in _SHIPPED.items()}

# The realistic sensing errors, off in the shipped instruments: {instrument: {field: (value, source, sure,
# note)}}. Like the shipped biases (uncompensated over 10 degC), they are what stays without a calibration
# after fitting. The air springs' sensors keep their nominal sensitivity (their bias is a full-scale accuracy).
REALISTIC = {
    "adxl355": {"scale_factor_error": (0.08 / 3.0, "sensitivity", "A",
                                       "the +-8 % part-to-part sensitivity taken as 3 sigma, not calibrated")},
    "adxl357": {"scale_factor_error": (0.08 / 3.0, "sensitivity", "A",
                                       "the +-8 % part-to-part sensitivity taken as 3 sigma, not calibrated")},
    "iepe_axle_box": {"scale_factor_error": (0.01, "IEPE calibration", "A",
                                             "the certificate's sensitivity used: its 2 % (k = 2) uncertainty")},
    "adis16470": {"scale_factor_error": (0.005 / 3.0, "ADIS16470 calibration", "A",
                                         "the factory calibration's +-0.5 % taken as 3 sigma")},
}


def value_source(name, field_name, value):
    """(source, sure, note) of an instrument's field value: the realistic one's where it is that, the shipped
    one's where it is the shipped value (the field's own for an instrument of a sensor file), else set in the
    sensor file."""
    realistic = REALISTIC.get(name, {}).get(field_name)
    if realistic is not None and realistic[0] == value:
        return realistic[1:]
    base = INSTRUMENTS.get(name)
    if base is not None and getattr(base, field_name) != value:
        return "config", "-", "set in the sensor file"
    meta = next(f.metadata for f in fields(Instrument) if f.name == field_name)
    return INSTRUMENT_SOURCES.get(name, {}).get(field_name, (meta["source"], meta["sure"], meta["note"]))


INSTRUMENT_FIELDS = tuple(f.name for f in fields(Instrument) if f.metadata)


def with_changes(inst: Instrument, changes):
    """The instrument with the changes {field: value} (from a sensor file), checked; an unknown field is a
    ValueError naming the accepted ones."""
    unknown = sorted(set(changes) - set(INSTRUMENT_FIELDS))
    if unknown:
        raise ValueError(f"instrument {inst.name}: unknown field(s) {', '.join(unknown)}; the fields are "
                         f"{', '.join(INSTRUMENT_FIELDS)}")
    typed = {k: (int(v) if k in ("bits", "anti_alias_order") else float(v)) for k, v in changes.items()}
    return replace(inst, **typed).validated()
