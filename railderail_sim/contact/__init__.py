"""Wheel-rail contact models (numba cores): Hertz, Kalker linear theory and saturated creep laws,
FASTSIM, Kik-Piotrowski non-elliptic patches, Nadal's limit. See docs/contact-models.md."""
from .creep import (FASTSIM, LINEAR, POLACH, POLACH_DRY_A, POLACH_DRY_B, POLACH_DRY_KA,
                    POLACH_DRY_KS, POLACH_DRY_MU0, SHEN_HEDRICK_ELKINS, creep_forces,
                    kalker_coefficients, linear_forces, polach_forces, she_factor)
from .fastsim import (NX_DEFAULT, NY_DEFAULT, fastsim_core, fastsim_forces, fastsim_strip,
                      fastsim_tractions, flexibilities, traction_field)
from .hertz import (G_MIN, RATIO_MAX, combined_modulus, ellip_ke, hertz_force, hertz_guard_active,
                    hertz_patch, hertz_shape)
from .kik_piotrowski import (EPS_DEFAULT, NPROP, P_AEQ, P_AREA, P_BEQ, P_DELTA, P_J0, P_J1,
                             P_JM, P_LENGTH, P_N, P_P0, P_PMAX, P_WIDTH, P_XL0, P_Y0, P_YC,
                             P_YMAX, P_YMIN, kp_creep_forces, kp_delta_for_force, kp_normal,
                             kp_normal_force, kp_patches)
from .nadal import nadal_flange_angle, nadal_friction, nadal_limit

__all__ = [
    "LINEAR", "SHEN_HEDRICK_ELKINS", "POLACH", "FASTSIM",
    "POLACH_DRY_KA", "POLACH_DRY_KS", "POLACH_DRY_MU0", "POLACH_DRY_A", "POLACH_DRY_B",
    "creep_forces", "kalker_coefficients", "linear_forces", "polach_forces", "she_factor",
    "NX_DEFAULT", "NY_DEFAULT", "fastsim_core", "fastsim_forces", "fastsim_strip",
    "fastsim_tractions", "flexibilities", "traction_field",
    "G_MIN", "RATIO_MAX", "combined_modulus", "ellip_ke", "hertz_force", "hertz_guard_active",
    "hertz_patch", "hertz_shape",
    "EPS_DEFAULT", "NPROP", "P_N", "P_YMIN", "P_YMAX", "P_LENGTH", "P_WIDTH", "P_AREA", "P_YC",
    "P_PMAX", "P_DELTA", "P_Y0", "P_XL0", "P_P0", "P_AEQ", "P_BEQ", "P_J0", "P_J1", "P_JM",
    "kp_creep_forces", "kp_delta_for_force", "kp_normal", "kp_normal_force", "kp_patches",
    "nadal_flange_angle", "nadal_friction", "nadal_limit",
]
