"""Track alignment (curvature, cant, heading, position) and lateral excitation; see `alignment`."""
