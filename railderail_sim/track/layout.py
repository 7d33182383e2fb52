"""Layouts of the track's core arrays that the rest of the package names without the core: the elastic
track's constants and the co-running rails' degrees of freedom (`track.elastic`). No numba here, so that
the ROS interface and the monitor can read records without compiling anything."""
from ..record import Record


class RailDof(Record):
    """A co-running rail's degrees of freedom: its deflection from the unloaded place (positions) or their
    rates (velocities), track axes."""
    lateral = "m; m/s", "lateral deflection of the roll centre, + left"
    vertical = "m; m/s", "vertical deflection of the roll centre, + up"
    roll = "rad; rad/s", "roll about the roll centre, + about the track x axis (the head moves to the right)"


class ElasticTrack(Record):
    """The track's constants (array `support` of the core), per wheel's co-running rail."""
    elastic = "-", "1: the rails are co-running masses on springs and dampers; 0: rigid rails"
    lateral_mass = "kg", "mass moving laterally with the rail"
    vertical_mass = "kg", "mass moving vertically with the rail"
    roll_inertia = "kg m^2", "roll inertia about the roll centre"
    lateral_stiffness = "N/m", "lateral stiffness to ground"
    vertical_stiffness = "N/m", "vertical stiffness to ground"
    roll_stiffness = "N m/rad", "roll stiffness to ground"
    lateral_damping = "N s/m", "lateral damping to ground"
    vertical_damping = "N s/m", "vertical damping to ground"
    roll_damping = "N m s/rad", "roll damping to ground"
    roll_centre_depth = "m", "depth of the roll centre below the rail top"
    roll_centre_lateral = "m", "track-frame Y of the left rail's roll centre (the right one mirrored)"


N_RAIL_DOF = RailDof.size()
