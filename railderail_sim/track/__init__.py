"""Track alignment (curvature, cant, heading, position) and lateral excitation; see `alignment`."""
from .alignment import pack_track, curvature, cant, frame, section, lateral_defect, end_of_line  # noqa: F401
