"""The track: its ideal alignment (curvature, cant, heading, position; `alignment`) and where the rails
actually lie about it (irregularities and defects; `rails`)."""
