"""Methods on the model: critical speeds (`root_locus`, `limit_cycle`), the progressive trial and its
sweeps (`progressive_trial`, `sweep`), the report (`report`), and the contact calculator of a wheel/rail
pair (`wheel_rail_pair`, `contact_geometry`, `contact_case`, `contact_patch`). Import the modules
themselves: this file imports nothing."""
