"""`python -m railderail_sim.cli`: the `railderail` command."""
import sys

from . import main

sys.exit(main())
