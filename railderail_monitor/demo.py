"""`railderail demo`: the main job, as real ROS 2 nodes in separate processes.

Starts the recorder (railderail_monitor.recording.recorder), the monitor (railderail_monitor.node), a second
monitor in measured mode beside it (`railderail_onboard_monitor`, signals:=measured: the on-board
sensors' topics only) and the simulator (railderail_sim.ros.node, its shipped sensor set on) on the built-in
scenario — R = 1000 m, the paper's progressive trial from 200 km/h until a wheel derails — at 200 Hz of
simulated time, faster than real time (`--real-time-factor`, with /clock). It prints the alerts of both
as they arrive (/railderail/alerts and /railderail/onboard_alerts), each marked with its mode
([ground_truth] or [measured]), and, at the derailment, how long and how far before it each criterion
warned. `--no-sensors` runs without the sensors and the second monitor. The run folder
(`--out DIR`, default runs/demo-YYYYMMDD-HHMMSS) then holds:

  demo.mcap     every topic (railderail record)        demo.rrd     the Rerun views (headless)
  summary.json  alerts, derailment, lead times, rates   logs/        one log per node

`--rerun` (or `--rerun-connect URL`) also runs the viewer node, live, beside the others.

`--closed-loop` runs the speed supervision in the loop instead (docs/supervision.md): a constant over-speed
(`--speed-kmh`, default 320) on the curve after `--approach-m` of straight (default 3000 m), the monitor
supervising the speed against the survey's safe speeds (`--survey`, default the shipped survey of the Table 2
line) and commanding the emergency brake, which the simulator obeys; beside it, the same run without the
supervisor (the batch core, no ROS), which derails. Both alert streams are printed: the supervision's
(`speed_supervision`) and the response criteria's.

Ctrl-C stops the nodes in order (simulator and monitor, then the recorder, so the MCAP is complete)
and exits with status 130; the .rrd is then not written (`railderail replay demo.mcap --no-publish
--rrd demo.rrd` makes it).
"""
from __future__ import annotations

import argparse
import ctypes
import datetime
import math
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

from railderail_sim import jsonout
from railderail_sim.ros.node_parameters import REAL_TIME_FACTOR_RANGE

from .recording.recorder import delivery, delivery_text, lost_count, recorded_counts
from .supervision.demo_loop import SHIPPED_SURVEY, closed_loop_summary, closed_loop_survey, open_loop_run
from .warning.alerts import label, lead_times, margin_kmh, user_alert
from .warning.limits import SEVERITY_NAMES, default_limits

NODES = {  # name: python -m module
    "recorder": "railderail_monitor.recording.recorder",
    "monitor": "railderail_monitor.node",
    "onboard": "railderail_monitor.node",
    "simulator": "railderail_sim.ros.node",
}
ONBOARD_NODE = "railderail_onboard_monitor"
ONBOARD_ARGS = ["--ros-args", "-r", f"__node:={ONBOARD_NODE}", "-p", "signals:=measured"]


def cpu_ticks(pid):
    """A process's user and system CPU time so far, in clock ticks (/proc/PID/stat); None once it is gone."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except OSError:
        return None
    return int(fields[11]) + int(fields[12])


def wait_idle(pid, quiet_s=0.5, timeout=120.0, pause=time.sleep):
    """Wait until a process used no CPU for `quiet_s` (a node that worked through its queue), at most `timeout`;
    `pause(0.1)` between looks (the demo spins its listener there, which gets that node's last alerts)."""
    deadline = time.monotonic() + timeout
    last, since = cpu_ticks(pid), time.monotonic()
    while last is not None and time.monotonic() < deadline:
        pause(0.1)
        now = cpu_ticks(pid)
        if now != last:
            last, since = now, time.monotonic()
        elif time.monotonic() - since >= quiet_s:
            return


def _child_setup():
    """In the child: default SIGINT (a background job may inherit it ignored) and SIGTERM when the
    demo dies, so that no node outlives it."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    try:
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGTERM)   # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


class Node:
    """A child process whose stderr and stdout go to a log file; `echo(line)` sees stderr lines."""

    def __init__(self, name, args, log_dir, echo=None):
        self.name = name
        self.log_path = log_dir / f"{name}.log"
        self.log = open(self.log_path, "w")
        self.process = subprocess.Popen(args, stdout=self.log, stderr=subprocess.PIPE, text=True,
                                        start_new_session=True, preexec_fn=_child_setup)
        self.lines = []
        self.thread = threading.Thread(target=self._pump, args=(echo,), daemon=True)
        self.thread.start()

    def _pump(self, echo):
        for line in self.process.stderr:
            self.log.write(line)
            self.log.flush()
            self.lines.append(line)
            if echo is not None:
                echo(line)

    def stop(self, timeout=15.0):
        """SIGINT, then SIGKILL after `timeout`; returns the exit status."""
        if self.process.poll() is None:
            self.process.send_signal(signal.SIGINT)
            try:
                self.process.wait(timeout)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        self.thread.join(5.0)
        self.log.close()
        return self.process.returncode


def simulator_parameters(args):
    """The simulator node's parameters of the demo: the paper's staircase on --radius, a catalogue's
    scenario (--catalogue, --scenario, --seed), or the closed loop's over-speed approach (--closed-loop)."""
    run = {"publish_rate": float(args.rate), "real_time_factor": float(args.real_time_factor),
           "contact_model": args.contact_model, "wait_for_subscribers": SUBSCRIBERS,
           **({} if args.no_sensors else {"sensors": "shipped", "wait_for_sensor_subscribers": SENSOR_SUBSCRIBERS})}
    if args.closed_loop:
        if args.scenario is not None or args.catalogue is not None:
            raise ValueError("--closed-loop runs its own over-speed approach: give it without --catalogue")
        return {"radius": float(args.radius), "speed_mode": "constant", "speed_kmh": float(args.speed_kmh),
                "approach_m": float(args.approach_m), **run}
    if args.scenario is None and args.catalogue is None:
        return {"radius": float(args.radius), "speed_mode": "progressive", "speed_kmh": float(args.start_kmh), **run}
    return {**catalogue_parameters(args.catalogue, args.scenario, args.seed), **run}


def catalogue_parameters(path, name, seed=None):
    """The simulator node's parameters of one catalogue scenario (its first seed unless `seed`); no faults
    given as no parameter (rcl cannot type an empty array on the command line)."""
    from .evaluation import catalogue
    if name is None:
        raise ValueError("--catalogue needs --scenario NAME")
    entries = {e.name: e for e in catalogue.load(None if path in (None, "shipped") else path)}
    if name not in entries:
        raise ValueError(f"--scenario {name!r} is not in the catalogue; its scenarios are {', '.join(entries)}")
    e = entries[name]
    seed = e.seeds[0] if seed is None else seed
    if seed not in e.seeds:
        raise ValueError(f"--seed {seed} is not one of the scenario's seeds {list(e.seeds)}")
    if math.isinf(e.radius_m):
        raise ValueError(f"scenario {name!r} runs on straight track, which the simulator node does not model "
                         "(its line is always the Table 2 curve)")
    if e.defect or not math.isnan(e.approach_m):
        raise ValueError(f"scenario {name!r} has a track defect or a longer approach, which the simulator node's "
                         "parameters do not take (give the defect as an irregularity file instead)")
    if e.vehicle_set != "hs19":
        raise ValueError(f"scenario {name!r} runs the suspension set {e.vehicle_set}, which the simulator node's "
                         "parameters do not take (it runs hs19)")
    irregularity = str(Path(e.folder, e.irregularity)) if e.irregularity.endswith(".csv") else e.irregularity
    return {"radius": e.radius_m, "speed_mode": "progressive" if e.progressive else "constant",
            "speed_kmh": 200.0 if e.progressive else e.speed_kmh, "cant_mm": e.cant_mm, "friction": e.friction,
            "irregularity": irregularity, "irregularity_seed": seed, "track": e.track,
            "line_length_m": 0.0 if math.isnan(e.line_length_m) else e.line_length_m,
            "wind_speed_m_s": e.wind_speed_m_s, "wind_direction_deg": 90.0, "gust": e.gust,
            **({"faults": list(e.faults)} if e.faults else {})}


def ros_args(parameters):
    out = ["--ros-args"]
    for name, value in parameters.items():
        out += ["-p", f"{name}:={value}"]
    return out


SUBSCRIBERS = 3          # the simulator starts once the monitor, the recorder and the demo's listener subscribe
SENSOR_SUBSCRIBERS = 2   # and, with the sensors, the measured-mode monitor and the recorder to every sensor topic


class Listener:
    """The demo's own rclpy node: alerts, the derailment event and the final status; the simulator counts
    it among the subscribers it waits for (`ros.interface.count_as_subscriber`)."""

    def __init__(self, say):
        import rclpy
        from rclpy.executors import SingleThreadedExecutor
        from rclpy.signals import SignalHandlerOptions

        from railderail_sim.ros import interface as m

        self.rclpy, self.m = rclpy, m
        rclpy.init(signal_handler_options=SignalHandlerOptions.NO)   # Ctrl-C stays a KeyboardInterrupt here
        self.node = rclpy.create_node("railderail_demo")
        self.executor = SingleThreadedExecutor()
        self.executor.add_node(self.node)
        self.say = say
        self.alerts, self.derailment, self.final_status, self.final_state = [], None, None, None
        self.onboard_alerts = []
        self.received_at = {}
        self.node.create_subscription(m.Alert, m.ALERTS, self.on_alert, m.ALERT_QOS)
        self.node.create_subscription(m.Alert, m.ONBOARD_ALERTS, self.on_onboard_alert, m.ALERT_QOS)
        self.node.create_subscription(m.DerailmentEvent, m.DERAILMENT, self.on_derailment, m.LATCHED)
        self.brakes = []
        self.node.create_subscription(m.BrakeCommand, m.BRAKE, self.on_brake, m.BRAKE_QOS)
        self.node.create_subscription(m.VehicleStatus, m.FINAL_STATUS, self.on_final, m.LATCHED)
        m.count_as_subscriber(self.node)

    def on_alert(self, msg):
        a = dict(self.m.alert_dict(msg), signals="ground_truth")
        self.alerts.append(a)
        self.say(f"  ALERT  [ground_truth] t = {a['time_s']:7.3f} s  s = {a['track_position']:7.1f} m  "
                 f"{a['speed'] * 3.6:5.1f} km/h  {a['message']}")

    def on_onboard_alert(self, msg):
        a = dict(self.m.alert_dict(msg), signals="measured", place=msg.header.frame_id)
        self.onboard_alerts.append(a)
        self.say(f"  ALERT  [measured]     t = {a['time_s']:7.3f} s  s = {a['track_position']:7.1f} m  "
                 f"{a['speed'] * 3.6:5.1f} km/h  {a['message']}")

    def on_brake(self, msg):
        b = dict(time_s=self.m.seconds(msg.header.stamp), sample=msg.sample, track_position_m=msg.track_position,
                 speed_kmh=msg.speed * 3.6, release_speed_kmh=msg.release_speed * 3.6, reason=msg.reason)
        self.brakes.append(b)
        self.say(f"  BRAKE  [supervision]  t = {b['time_s']:7.3f} s  s = {b['track_position_m']:7.1f} m  "
                 f"{b['speed_kmh']:5.1f} km/h  emergency brake commanded, down to {b['release_speed_kmh']:.1f} km/h")

    def on_derailment(self, msg):
        self.derailment = self.m.derailment_dict(msg)

    def on_final(self, msg):
        self.final_status, self.final_state = msg.message, msg.state

    def spin_once(self, timeout):
        self.executor.spin_once(timeout_sec=timeout)

    def close(self):
        self.executor.shutdown()
        self.node.destroy_node()
        self.rclpy.try_shutdown()


ENTRY_RULE = ("an alert below the trial's entry speed plus one step ({limit:g} km/h) is marked 'entry': the trial "
              "starts at a speed the car runs safely, so such an alert says its level lies below this curve's "
              "normal running at that speed, not that a derailment comes; it is no warning")


def entry_speed_kmh(sim_params):
    """The speed below which an alert is the trial's entry, not a warning (ENTRY_RULE): the progressive trial's
    start plus one step; None for a run at constant speed (no entry to set apart)."""
    if sim_params.get("speed_mode") != "progressive":
        return None
    from railderail_sim.ros.node import PARAMETERS
    step = sim_params.get("step_kmh", next(spec.default for spec in PARAMETERS if spec.name == "step_kmh"))
    return float(sim_params["speed_kmh"]) + float(step)


def is_entry(alert, entry_kmh):
    return entry_kmh is not None and alert["speed"] * 3.6 < entry_kmh


def lead_text(lead_s, lead_m, margin):
    """How far before the derailment: km/h of speed still gained, metres and seconds."""
    return f"{margin:5.1f} km/h {lead_m:7.0f} m {lead_s:7.2f} s"


def lead_table(alerts, derailment, entry_kmh=None):
    """Lines: every alert with its margin (km/h), lead distance (m) and time (s) before the derailment."""
    lines = []
    for a in alerts:
        lead = lead_text(derailment["time_s"] - a["time_s"], derailment["track_position_m"] - a["track_position"],
                         margin_kmh(a, derailment))
        lines.append(f"  {label(a['criterion']):31s} {SEVERITY_NAMES[a['severity']]:8s} ws{a['wheelset']} "
                     f"{a['wheel_side'] or '-':5s} {a['rail_side'] or '-':5s} {a['speed'] * 3.6:6.1f} km/h  {lead}"
                     + ("  entry: no warning" if is_entry(a, entry_kmh) else ""))
    return lines


def measured_leads(alerts, derailment, entry_kmh=None):
    """{criterion at place: first measured alert's time_s, track_position_m, speed_kmh, lead_s, lead_m,
    margin_kmh (NaN without a derailment), entry (ENTRY_RULE)}."""
    out = {}
    for a in alerts:
        key = f"{a['criterion']} at {a['place']}"
        if key not in out:
            lead_s = derailment["time_s"] - a["time_s"] if derailment else math.nan
            lead_m = derailment["track_position_m"] - a["track_position"] if derailment else math.nan
            out[key] = dict(time_s=a["time_s"], track_position_m=a["track_position"], speed_kmh=a["speed"] * 3.6,
                            lead_s=lead_s, lead_m=lead_m, margin_kmh=margin_kmh(a, derailment),
                            entry=is_entry(a, entry_kmh))
    return out


def first_alert_lines(leads, derailment, name):
    """Lines: the first alert of each key, its speed and how far before the derailment."""
    lines = []
    for key, v in sorted(leads.items(), key=lambda kv: kv[1]["time_s"]):
        lead = lead_text(v["lead_s"], v["lead_m"], v["margin_kmh"]) if derailment else "no derailment followed"
        lines.append(f"  {name(key):55s} {v['speed_kmh']:6.1f} km/h  {lead}"
                     + ("  entry: no warning" if v.get("entry") else ""))
    return lines


def measured_summary(alerts, derailment, entry_kmh=None):
    """Lines about the measured-mode monitor's alerts beside the derailment."""
    if not alerts:
        return "measured-mode monitor: no alert" + (" before the derailment" if derailment else "")
    leads = measured_leads(alerts, derailment, entry_kmh)
    lines = [f"measured-mode monitor: {len(alerts)} alerts; the first of each criterion and place (speed at it"
             + ("; before the derailment: km/h still gained, m, s" if derailment else "") + "):"]
    lines += first_alert_lines(leads, derailment,
                               lambda key: "{} at {}".format(label(key.split(" at ")[0]), key.split(" at ")[1]))
    return "\n".join(lines)


def pace(report):
    """{achieved, requested samples per wall second, behind}: behind when the simulator managed less than 95 %
    of the rate asked for (requested 0: as fast as possible, never behind)."""
    achieved, requested = report["achieved_samples_per_s"], report["requested_samples_per_s"]
    return dict(achieved_samples_per_s=achieved, requested_samples_per_s=requested,
                behind=bool(requested > 0 and achieved < 0.95 * requested))


def pace_text(p, rate):
    """One line on the simulator's pace: a warning when it fell behind."""
    achieved, requested = p["achieved_samples_per_s"], p["requested_samples_per_s"]
    if p["behind"]:
        return (f"WARNING: the simulator fell behind: {achieved:.1f} of the requested {requested:g} samples/s "
                f"({achieved / rate:.2f} x real time instead of {requested / rate:g}; the machine is slower or "
                "busier than the rate asked for: lower --real-time-factor, or expect the run to take longer)")
    return f"simulator pace: {achieved:.1f} samples/s (requested {requested:g}" + \
        (", as fast as possible)" if requested == 0 else ")")


def command_prefix():
    """How the user ran railderail, for the hints: the script's path (e.g. .venv/bin/railderail), or this
    Python with -m."""
    script = Path(sys.argv[0])
    if script.name == "railderail":
        return str(script)
    return f"{sys.executable} -m railderail_sim.cli"


def rerun_command():
    """The Rerun viewer beside this Python (the venv's), else bare `rerun`."""
    beside = Path(sys.executable).parent / "rerun"
    return str(beside) if beside.exists() else "rerun"


def run_demo(args, say=print):
    started = time.monotonic()
    out = Path(args.out) if args.out else Path("runs") / datetime.datetime.now().strftime("demo-%Y%m%d-%H%M%S")
    (out / "logs").mkdir(parents=True, exist_ok=True)
    mcap_path, rrd_path, summary_path = out / "demo.mcap", out / "demo.rrd", out / "summary.json"
    limits = default_limits()
    sim_params = simulator_parameters(args)
    survey = closed_loop_survey(args.survey or SHIPPED_SURVEY, sim_params, out) if args.closed_loop else None
    pace_asked = ("as fast as possible" if args.real_time_factor == 0 else
                  f"asking for {args.real_time_factor:g} x real time ({args.rate * args.real_time_factor:g} samples/s; "
                  "the end says if the machine kept up)")
    if args.closed_loop:
        say(f"railderail demo, closed loop: R = {args.radius:g} m at a constant {args.speed_kmh:g} km/h after "
            f"{args.approach_m:g} m of straight, the speed supervised against {survey}; {args.rate:g} Hz, "
            f"{pace_asked}; run folder {out}")
    else:
        say(f"railderail demo: R = {args.radius:g} m, progressive trial from {args.start_kmh:g} km/h, "
            f"{args.rate:g} Hz, {pace_asked}; run folder {out}")
    say("starting the recorder, the monitor and the simulator (the first run in a fresh checkout also "
        "compiles the core: about a minute)")
    listener = Listener(say)
    python = sys.executable
    metadata = [f"monitor.{k}={v}" for k, v in limits.as_dict().items()]
    metadata += [f"simulator.{k}={v}" for k, v in sim_params.items()]
    nodes = {}

    def echo_sim(line):
        if ("samples/s" in line) or ("ERROR" in line) or ("error" in line) or ("ready:" in line):
            say("  sim    " + line.split("]: ", 1)[-1].rstrip())

    status = 0
    try:
        nodes["recorder"] = Node("recorder", [python, "-m", NODES["recorder"], str(mcap_path)]
                                 + [a for kv in metadata for a in ("--metadata", kv)], out / "logs")
        nodes["monitor"] = Node("monitor", [python, "-m", NODES["monitor"]]
                                + (ros_args({"supervision": survey}) if survey else []), out / "logs")
        if not args.no_sensors:
            nodes["onboard"] = Node("onboard", [python, "-m", NODES["onboard"]] + ONBOARD_ARGS, out / "logs")
            # the simulator waits for the subscribers of the states, which this node is not among: wait for it
            up = time.monotonic() + 120.0
            while not any("monitoring" in line for line in nodes["onboard"].lines):
                if nodes["onboard"].process.poll() is not None or time.monotonic() > up:
                    raise RuntimeError(f"the measured-mode monitor did not start; see {nodes['onboard'].log_path}")
                listener.spin_once(0.05)
        if args.rerun or args.rerun_connect:
            sink = ["--connect", args.rerun_connect] if args.rerun_connect else ["--spawn"]
            nodes["viewer"] = Node("viewer", [python, "-m", "railderail_monitor.views.viewer_node"] + sink, out / "logs")
        nodes["simulator"] = Node("simulator", [python, "-m", NODES["simulator"]] + ros_args(sim_params),
                                  out / "logs", echo=echo_sim)
        deadline = time.monotonic() + args.timeout
        while nodes["simulator"].process.poll() is None:
            listener.spin_once(0.1)
            for name in ("recorder", "monitor", "onboard"):
                if name in nodes and nodes[name].process.poll() is not None:
                    raise RuntimeError(f"the {name} node stopped (status {nodes[name].process.returncode}); "
                                       f"see {nodes[name].log_path}")
            if time.monotonic() > deadline:
                raise RuntimeError(f"the run took longer than --timeout {args.timeout:g} s; stopped")
        code = nodes["simulator"].process.wait()
        linger = time.monotonic() + 1.5             # late alerts and the latched final messages
        while time.monotonic() < linger or (listener.final_status is None and time.monotonic() < linger + 3):
            listener.spin_once(0.1)
        # 0: the run ended; 1 is a result only with the final status of a divergence (a failure to start, or
        # any other error, is not the end of a run, and must not be reported as one)
        diverged = listener.final_state == listener.m.msgs.VehicleStatus.STATE_DIVERGED
        if not (code == 0 or code == 1 and diverged):
            raise RuntimeError(f"the simulator node failed (status {code}"
                               f"{'' if code != 1 else ', no final status of a divergence'}); "
                               f"see {nodes['simulator'].log_path}")
        if "viewer" in nodes:
            nodes.pop("viewer").stop()
        if "onboard" in nodes:
            # a Python node behind a simulator faster than real time may still be working through the sensor
            # messages in its queue: stopping it now would lose them
            wait_idle(nodes["onboard"].process.pid, pause=listener.spin_once)
        codes = {name: nodes.pop(name).stop() for name in ("monitor", "onboard") if name in nodes}
        linger = time.monotonic() + 1.0             # what the monitors published as they stopped
        while time.monotonic() < linger:
            listener.spin_once(0.1)
        codes["recorder"] = nodes.pop("recorder").stop()
        if any(codes.values()):
            raise RuntimeError("exit status " + ", ".join(f"{k} {v}" for k, v in codes.items())
                               + f"; see {out / 'logs'}")
    except KeyboardInterrupt:
        say("\nCtrl-C: stopping the nodes")
        status = 130
    except RuntimeError as error:
        say(f"railderail demo: error: {error}")
        status = 1
    finally:
        for name in ("simulator", "viewer", "monitor", "onboard", "recorder"):  # the recorder last: its file holds all
            if name in nodes:
                nodes[name].stop()
        listener.close()
    if status == 130:
        say(f"stopped; the recording so far is {mcap_path}")
        return status
    wall_run = time.monotonic() - started

    d = listener.derailment
    entry_kmh = entry_speed_kmh(sim_params)
    say("")
    if d is not None:
        say(f"DERAILED at t = {d['time_s']:.3f} s, s = {d['track_position_m']:.1f} m, {d['speed_kmh']:.1f} km/h: "
            f"wheelset {d['wheelset']} {d['wheel_side']} ({d['rail_side']} rail), {d['mechanism'].replace('_', ' ')}")
        if listener.alerts:
            say("alerts (criterion, level, wheelset, wheel, rail, speed at the alert; before the derailment: km/h "
                "still gained, metres, seconds):")
            for line in lead_table(listener.alerts, d, entry_kmh):
                say(line)
        else:
            say("no alert came before the derailment")
    else:
        say(f"the run stopped without a derailment: {listener.final_status or 'no final status received'}")
    leads = lead_times(listener.alerts, d)
    for v in leads.values():
        v["entry"] = entry_kmh is not None and v["speed_kmh"] < entry_kmh
    if leads:
        say("first alert of each criterion:")
        for line in first_alert_lines(leads, d, lambda key: "{} ({})".format(label(key.split("/")[0]),
                                                                              key.split("/")[1])):
            say(line)
    onboard_leads = None if args.no_sensors else measured_leads(listener.onboard_alerts, d, entry_kmh)
    if not args.no_sensors:
        say(measured_summary(listener.onboard_alerts, d, entry_kmh))
    entry_rule = None if entry_kmh is None else ENTRY_RULE.format(limit=entry_kmh)
    if entry_rule and any(v["entry"] for v in [*leads.values(), *(onboard_leads or {}).values()]):
        say("entry: " + entry_rule)
    open_loop = None
    if args.closed_loop:
        open_loop = open_loop_run(sim_params)
        say(closed_loop_summary(listener.brakes, d, open_loop))
    sim_log = (out / "logs" / "simulator.log").read_text()
    rate_line = next((l for l in sim_log.splitlines() if "published" in l), "")
    report = listener.m.run_report(sim_log)
    logs = {name: next((l for l in (out / "logs" / f"{name}.log").read_text().splitlines() if "processed" in l), "")
            for name in ("monitor", "onboard") if (out / "logs" / f"{name}.log").exists()}
    simulator_pace = None if report is None else pace(report)
    if simulator_pace is not None:
        say(pace_text(simulator_pace, args.rate))
    for name, line in logs.items():
        if line:
            say(f"{name + ':':10s} " + line.split("] ", 1)[-1])
    mon_line = logs.get("monitor", "")
    recording = None if report is None else delivery(report["published"], recorded_counts(mcap_path))
    say("recorder: " + (delivery_text(recording) if recording is not None else
                        "the simulator's log has no run report: what the recording lost is not known"))
    if not args.no_rrd:
        from .recording.replay import read_recording, viewed, write_rrd
        t0 = time.monotonic()
        write_rrd(read_recording(mcap_path, decode=viewed), rrd_path, limits)
        say(f"wrote {rrd_path} in {time.monotonic() - t0:.1f} s")
    summary = dict(run_folder=str(out), mcap=str(mcap_path), rrd=None if args.no_rrd else str(rrd_path),
                   simulator=sim_params, limits=limits.as_dict(), derailment=d, final_status=listener.final_status,
                   alerts=[user_alert(a) for a in listener.alerts], lead_times=leads,
                   simulator_log=rate_line.split("]: ", 1)[-1], simulator_pace=simulator_pace,
                   recording_delivery=recording,
                   recording_lost=None if recording is None else lost_count(recording),
                   monitor_log=mon_line.split("] ", 1)[-1],
                   onboard_alerts=None if args.no_sensors else [user_alert(a) for a in listener.onboard_alerts],
                   onboard_lead_times=onboard_leads, entry_rule=entry_rule,
                   onboard_log=logs.get("onboard", "").split("] ", 1)[-1] or None,
                   closed_loop=None if not args.closed_loop else dict(survey=survey, brake_commands=listener.brakes,
                                                                      without_supervision=open_loop),
                   wall_time_s=time.monotonic() - started,
                   wall_time_run_s=wall_run)
    jsonout.write(summary_path, summary)
    say(f"run folder: {out}  (demo.mcap, {'' if args.no_rrd else 'demo.rrd, '}summary.json, logs/); "
        f"wall time {summary['wall_time_s']:.0f} s")
    say(f"review it: {command_prefix()} replay {mcap_path} --no-publish"
        + ("" if args.no_rrd else f"   |   {rerun_command()} {rrd_path}"))
    return 0 if d is not None or listener.final_state is not None else 1


def add_arguments(parser):
    parser.add_argument("--out", metavar="DIR", help="run folder (default runs/demo-YYYYMMDD-HHMMSS)")
    parser.add_argument("--radius", type=float, default=1000.0, help="curve radius, m (default 1000)")
    parser.add_argument("--start-kmh", type=float, default=200.0, help="staircase start speed, km/h (default 200)")
    parser.add_argument("--rate", type=float, default=200.0, help="publish rate, Hz of simulated time (default 200)")
    parser.add_argument("--real-time-factor", type=float, default=3.0,
                        help="simulated seconds per second (default 3; 0 = as fast as possible; at most "
                        f"{REAL_TIME_FACTOR_RANGE[1]:g})")
    parser.add_argument("--contact-model", default="hertz", choices=("hertz", "discrete"))
    parser.add_argument("--no-rrd", action="store_true", help="do not write the Rerun file")
    parser.add_argument("--no-sensors", action="store_true",
                        help="no on-board sensors and no measured-mode monitor (the ground truth only)")
    parser.add_argument("--rerun", action="store_true", help="also show the run live in a Rerun viewer (spawned)")
    parser.add_argument("--rerun-connect", metavar="URL", help="also stream it live to a running Rerun viewer")
    parser.add_argument("--timeout", type=float, default=900.0, help="stop the run after this many s (900)")
    parser.add_argument("--catalogue", nargs="?", const="shipped", metavar="FILE.yaml",
                        help="run a scenario of a catalogue (no FILE: the shipped one) instead of the staircase")
    parser.add_argument("--scenario", metavar="NAME", help="the catalogue's scenario to run (with --catalogue)")
    parser.add_argument("--seed", type=int, default=None, help="its seed (default: the scenario's first)")
    parser.add_argument("--closed-loop", action="store_true",
                        help="the speed supervision in the loop: a constant over-speed after a straight approach, "
                        "braked by the supervisor's command; beside it the same run without (docs/supervision.md)")
    parser.add_argument("--speed-kmh", type=float, default=320.0,
                        help="--closed-loop: the constant speed, km/h (default 320)")
    parser.add_argument("--approach-m", type=float, default=3000.0,
                        help="--closed-loop: straight before the curve's transition, m (default 3000)")
    parser.add_argument("--survey", metavar="FILE.json",
                        help="--closed-loop: the survey whose safe speeds are supervised (`railderail survey "
                        "LINE.yaml --json`; default the shipped survey of the Table 2 line)")


def command(parser: argparse.ArgumentParser):
    add_arguments(parser)

    def run(args):
        from railderail_sim.ros.node import PARAMETERS

        table = {spec.name: spec for spec in PARAMETERS}     # the simulator node's own checks, before it starts
        for name, value in simulator_parameters(args).items():
            table[name].checked(value)
        return run_demo(args, say=lambda text: print(text, flush=True))
    return run
