"""The track: its ideal alignment (curvature, cant, heading, position; `alignment`), where the rails
actually lie about it (the core's rail offsets; `rails`) and the irregularities that say so (spectra, random
samples, the CSV format; `irregularity`)."""
