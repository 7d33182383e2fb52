"""Braking in the simulator: the braking model (`braking`: the emergency deceleration bands, brake build-up,
speed over distance) and the closed loop of the batch path (`closed_loop`: a run braked on a controller's
command). The supervisor that commands it lives in railderail_monitor.supervision; docs/supervision.md."""
