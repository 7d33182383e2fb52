"""The on-line warning on the simulator's ground truth (wheelset states and contact forces): the criteria's
levels and their parameter file (`limits`, `monitor_params`), the values compared (`quantities`), the alarm
mechanics (`alarms`), the alert and its wording (`alerts`), the streaming monitor (`monitor`) and TCRP's
flange-climb distance (`climb_distance`). No ROS here: the node (`railderail_monitor.node`) runs `Monitor`."""
