"""Wheel-rail contact models (numba cores): contact geometry and search, Hertz, Kalker linear theory and
saturated creep laws, FASTSIM, Kik-Piotrowski non-elliptic patches, the exact half-space solver,
Nadal's limit. See docs/contact-models.md. Import the modules themselves (`from railderail_sim.contact
import hertz`): this file imports nothing, so that loading one model does not compile them all."""
