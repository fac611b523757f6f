"""``python -m gear_dyn.cli``."""

from gear_dyn.cli.app import main

raise SystemExit(main())
