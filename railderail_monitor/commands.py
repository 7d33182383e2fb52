"""The `railderail` subcommands of the ROS 2 product, registered with `railderail_sim.cli` through the
entry-point group `railderail.commands` (setup.py). Kept free of imports: `railderail --help` reads it."""

COMMANDS = (
    ("demo", "the main job: simulator, monitor and recorder nodes over the R = 1000 m trial, with alerts, "
     "MCAP and Rerun files", "railderail_monitor.demo:command"),
    ("replay", "replay an MCAP recording on the ROS topics, in Rerun (--rrd) or as alerts (--json)",
     "railderail_monitor.recording.replay:command"),
    ("record", "record every /railderail topic to an MCAP file", "railderail_monitor.recording.recorder:command"),
    ("recover", "a complete MCAP (summary, footer) of everything readable in a cut-off recording, or of its "
     "sensor topics only",
     "railderail_monitor.recording.recover:command"),
    ("import-imu", "a logger's CSV of on-board sensor readings as a recording the measured-mode monitor replays, "
     "with its sensor file", "railderail_monitor.recording.import_imu:command"),
    ("view", "show the live /railderail topics in Rerun (--rrd FILE for a file)",
     "railderail_monitor.views.viewer_node:command"),
    ("monitor-params", "the monitor's parameter file (thresholds) of a wheel, rail, friction and vehicle set",
     "railderail_monitor.warning.monitor_params:command"),
    ("assess", "running behaviour as EN 14363 and EN 12299 define it (safety, track loading, ride, comfort) of a "
     "run (.npz) or a recording (.mcap); --json, --plot, --study DIR", "railderail_monitor.recording.assess:command"),
    ("warnings", "warning quality: lead time and false alarms of each criterion over the six radii, or over a "
     "scenario catalogue with thresholds swept (--catalogue)",
     "railderail_monitor.evaluation.over_radii:command"),
    ("onboard-study", "at which speed and how early the bogie-instability rules on the measured frame accelerations "
     "see hunting (failed yaw dampers) and a broken primary spring (--out DIR)",
     "railderail_monitor.evaluation.onboard_study:command"),
)

# `railderail simulate --supervision` runs through this (railderail_sim.cli.methods finds it by name)
SUPERVISION = "railderail_monitor.supervision.loop:simulate_supervised"
