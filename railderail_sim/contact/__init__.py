"""Wheel-rail contact (numba core): geometry (trace-line search) and its precomputed table, Hertz,
Kalker's linear theory and saturated creep laws, FASTSIM, Kik-Piotrowski non-elliptic patches, the exact
half-space solver, Nadal's limit, rigid-contact tables and equivalent conicity, and the forces of one
wheel (`wheelset`). See docs/contact-models.md. Import the modules themselves."""
