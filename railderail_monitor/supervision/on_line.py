"""The speed supervision in the monitor node (ground truth): the supervisor fed each wheelset-states sample's
car-body position and speed, its level rises published as Alerts of the criterion `speed_supervision` and its
intervention as an emergency brake command (railderail_msgs/BrakeCommand on /railderail/brake_command, which
the simulator node obeys: the loop closed through ROS).

Levels on the Alert message: INDICATION -> SEVERITY_INFO, WARNING -> SEVERITY_WARNING, INTERVENTION ->
SEVERITY_CRITICAL. The Alert's value is the speed (m/s) and its threshold the target's speed limit (m/s); its
message gives the margin (km/h) and the time to the last braking point (s). The targets come from a survey's
JSON (`loop.survey_targets`); the front of the train is the leading wheelset, the car body's position plus the
bogie's and the wheelbase's semi-distances of the car.
"""
from railderail_sim.parameters import vehicle_parameters
from railderail_sim.supervision.braking import BrakingModel

from ..warning.alerts import AlertRecord
from ..warning.limits import SEVERITY_CRITICAL, SEVERITY_INFO, SEVERITY_WARNING
from .curves import INDICATION, INTERVENTION, KMH, LEVELS, WARNING, SupervisionLimits
from .loop import survey_targets
from .supervisor import Supervisor

CRITERION = "speed_supervision"
SEVERITY = {INDICATION: SEVERITY_INFO, WARNING: SEVERITY_WARNING, INTERVENTION: SEVERITY_CRITICAL}


def alert_text(alert):
    """One line for people of a supervisor's Alert (supervisor.Alert)."""
    return (f"{alert.level}: speed supervision {alert.speed_kmh:.1f} km/h against {alert.limit_kmh:.1f} km/h, margin "
            f"{alert.margin_kmh:+.1f} km/h, {alert.time_to_intervention_s:.1f} s to the last braking point "
            f"({alert.reason})")


class OnLineSupervision:
    """The supervisor over a survey's targets for one car; `on_states` per sample gives (AlertRecords, the
    release speed of a brake to command or None)."""

    def __init__(self, survey, vehicle_set="hs19", adhesion="dry", limits=SupervisionLimits()):
        self.supervisor = Supervisor(survey_targets(survey), BrakingModel(adhesion=adhesion), limits)
        v = vehicle_parameters(vehicle_set)
        self.front_offset = v.bogie_semi_distance + v.wheelbase_semi
        self.commanded = False

    def on_states(self, t, sample, position, speed):
        before = len(self.supervisor.alerts)
        level = self.supervisor.step(t, position + self.front_offset, speed)
        records = [AlertRecord(t, sample, CRITERION, SEVERITY[LEVELS.index(a.level)], speed, a.limit_kmh * KMH, 0,
                               "", "", position, speed, alert_text(a))
                   for a in self.supervisor.alerts[before:]]
        brake = None
        if level == INTERVENTION and not self.commanded:
            brake = self.supervisor.release_speed
        self.commanded = self.supervisor.release_speed is not None
        return records, brake

    def reason(self):
        """The reason of the last alert (the target that set the level)."""
        return self.supervisor.alerts[-1].reason if self.supervisor.alerts else ""
