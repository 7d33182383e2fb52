"""Track alignment (curvature, cant, heading, position) and lateral excitation, see `alignment`; track
irregularities (spectra, random samples, the CSV format, the packed array of the core), see `irregularity`."""
