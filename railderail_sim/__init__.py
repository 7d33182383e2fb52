"""railderail simulator: CRH3 car on a curve, wheel-rail contact, derailment prediction.

Keep this file free of heavy imports (numba, rclpy): `railderail --help` imports it.
"""

__version__ = "0.1.0"
