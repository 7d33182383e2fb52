"""Layouts of the contact core's arrays (`record.Record`): the packed contact geometry's header, a contact
patch's row, the candidate list, the contact constants and a wheel's output record.

Kept apart from the numba code (and free of numba) so that the ROS side and the Python tools can read the
records without compiling or importing the core.
"""
from ..record import Record

MAX_PATCHES = 3                      # contact patches of one wheel at most
MAX_CANDIDATES = 6                   # contact minima followed within a step at most
KALKER_SEGMENTS = 18                 # segments of Kalker's Table E3 between its rows u = 0.1, 0.2, ..., 1.9
                                     # (creep.KALKER_C11 and the others: 19 rows)


class GeometryHeader(Record):
    """Header of the packed contact-geometry array cg (`pack_contact_geometry`); the wheel and rail
    tables, and the contact table if any, follow it."""
    wheel_points = "-", "points of the wheel grid"
    wheel_y0 = "m", "first wheel profile coordinate y_p of the grid"
    wheel_step = "m", "wheel grid step"
    rail_points = "-", "points of the rail grid (track frame, left rail)"
    rail_y0 = "m", "first track-frame Y of the rail grid"
    rail_step = "m", "rail grid step"
    nominal_radius = "m", "nominal rolling radius r0"
    rolling_circle_distance = "m", "lateral distance lw from the wheelset centre to the nominal rolling circle"
    rail_top_y = "m", "track-frame Y of the rail's highest point"
    rail_axis_y = "m", "track-frame Y of the rail head's axis at its top"
    flange_height = "m", "flange height above the nominal rolling circle"
    flange_tip_y = "m", "wheel profile coordinate y_p of the flange tip"
    rail_head_width = "m", "rail head width at the gauge-measuring depth"
    gauge_y = "m", "track-frame Y of the gauge point"
    # the contact table (`contact.table`)
    table = "-", "offset of the contact table's nodes in cg; 0 when there is none"
    table_u_points = "-", "nodes along the table's lateral axis u"
    table_u0 = "m", "first u of the table"
    table_u_step = "m", "u step of the table"
    table_roll_points = "-", "nodes along the table's roll axis"
    table_roll0 = "rad", "first roll of the table"
    table_roll_step = "rad", "roll step of the table"
    table_yaw_max = "rad", "largest yaw the table's second-order yaw terms serve"


H_SIZE = GeometryHeader.size()


class HertzShape(Record):
    """Hertz's contact shape of a patch at E* = 1 Pa: the semi-axes a = a_c N^(1/3), b = b_c N^(1/3) and
    the normal force N = C d^1.5; at a modulus E* they scale as E*^(-1/3), E*^(-1/3) and E* (exact)."""
    a_coefficient = "m N^(-1/3)", "a_c"
    b_coefficient = "m N^(-1/3)", "b_c"
    stiffness = "N m^-1.5", "C"


class Patch(Record):
    """One contact patch of a wheel: a row of the `patches` array, filled by the search (geometry, or
    the contact table) and, from `normal_force` on, by `contact.wheelset.wheel_forces`."""
    y = "m", "contact point on the rail: track-frame Y (left-wheel form)"
    z = "m", "contact point: track-frame Z"
    x = "m", "contact point: lead along the track from the wheelset centre"
    gap = "m", "vertical gap at the deepest point (negative = interpenetration)"
    slope = "-", "rail slope dZ/dY at the contact (tan of the contact angle)"
    wheel_y = "m", "wheel profile coordinate y_p of the contact"
    radius = "m", "wheel radius at the contact (NaN from the contact table)"
    curvature_b = "1/m", "half the relative lateral curvature, Hertz's B (NaN from the contact table)"
    curvature_a = "1/m", "half the relative longitudinal curvature, Hertz's A (NaN from the contact table)"
    grid_index = "-", "fine wheel grid index of the deepest point"
    normal_force = "N", "normal force (0 if the patch carries none)"
    approach = "m", "normal approach"
    half_length = "m", "semi-axis along x: Hertz, or the discrete patch's"
    half_width = "m", "semi-axis along the contact's lateral tangent: Hertz, or the discrete patch's"
    creep_a = "m", "semi-axis along x of the ellipse the creep law uses"
    creep_b = "m", "lateral semi-axis of the ellipse the creep law uses"
    hertz_a = "m", "Hertz semi-axis along x at the same load"
    hertz_b = "m", "lateral Hertz semi-axis at the same load"
    creepage_x = "-", "longitudinal creepage"
    creepage_y = "-", "lateral creepage in the contact plane"
    spin_creepage = "1/m", "spin creepage"
    creep_force_x = "N", "longitudinal creep force on the wheel"
    creep_force_lateral = "N", "lateral creep force on the wheel, in the contact plane"
    spin_moment = "N m", "spin moment on the wheel"
    weight = "-", "share weight of an equivalent-elliptic patch (see _set_weights)"
    hertz_shape = "-", "Hertz shape at E* = 1 Pa from the contact table (stiffness 0: not given)", (), HertzShape


P_COLS = Patch.size()


class Candidates(Record):
    """The contact minima of one wheel worth following within the next integration step: listed by a
    full search (`find_patches`, the contact table) and followed by `track_patches`."""
    count = "-", "number of minima listed"
    indices = "-", "their fine wheel grid indices", (MAX_CANDIDATES,)


CANDIDATES_SIZE = Candidates.size()


class KalkerPiece(Record):
    """One of Kalker's coefficients (C11, C22, C23 or C33) on one segment of Table E3 at the model's Poisson
    ratio, exactly: C = P(f) / Q(f), f in [0, 1] the fraction of the segment (`creep.kalker_table`)."""
    numerator = "-", "P's coefficients of f^0, f^1, f^2, f^3", (4,)
    denominator = "-", "Q's coefficients of f^0, f^1, f^2", (3,)


class ContactConstants(Record):
    """The contact constants array cp."""
    youngs_modulus = "Pa", "Young's modulus E of wheel and rail"
    combined_modulus = "Pa", "E* = E / (2 (1 - nu^2)) of two bodies of the same material"
    combined_modulus_cbrt = "Pa^(1/3)", "E*^(1/3): scales the contact table's Hertz shape (given at E* = 1 Pa)"
    shear_modulus = "Pa", "shear modulus G"
    poisson_ratio = "-", "Poisson's ratio"
    friction = "-", "friction coefficient"
    contact_damping = "s/m", "Hunt-Crossley coefficient chi: N = C d^1.5 (1 + chi d')"
    normal_model = "-", "NORMAL_HERTZ or NORMAL_DISCRETE"
    creep_model = "-", "creep law, one of creep.LINEAR, SHEN_HEDRICK_ELKINS, POLACH, FASTSIM"
    qp_min_load = "N", "vertical load below which Q/P is not evaluated (an unloaded wheel's ratio means nothing)"
    kalker = ("-", "Kalker's C11, C22, C23, C33 on each segment of Table E3 at poisson_ratio (`creep.kalker_table`)",
              (KALKER_SEGMENTS, 4), KalkerPiece)


C_SIZE = ContactConstants.size()


class WheelPatch(Record):
    """One contact patch in a wheel's output record."""
    lateral_position = "m", "contact point on the rail from the head axis, + field side"
    lead = "m", "contact point's lead along the track from the wheelset centre"
    length = "m", "patch length 2a along the track"
    width = "m", "patch width 2b across it"
    normal_force = "N", "normal force"
    contact_angle = "rad", "contact angle, + toward the flange"


class Wheel(Record):
    """A wheel's output record (right wheels in their mirrored, left-wheel form)."""
    wheel_lift = "m", "wheel lift hp: the nominal rolling circle's lowest point above the rail's highest point"
    lateral_force = "N", "lateral force Q on the rail, + toward the rail's field side"
    vertical_force = "N", "vertical force P on the rail, + down"
    longitudinal_force = "N", "longitudinal force on the rail"
    derailment_coefficient = "-", "Q/P (0 while P is below ContactConstants.qp_min_load)"
    contact_position = "m", "main patch (the most loaded one): lateral position on the rail from the head axis"
    contact_angle = "rad", "main patch: contact angle"
    patch_length = "m", "main patch: length 2a"
    patch_width = "m", "main patch: width 2b"
    contact_count = "-", "number of patches"
    min_gap = "m", "smallest wheel-rail gap (negative when in contact)"
    patches = "-", "every patch, in order across the wheel (unused rows 0)", (MAX_PATCHES,), WheelPatch


W_SIZE = Wheel.size()
WP_SIZE = WheelPatch.size()
