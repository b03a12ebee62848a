"""`python -m studies` is the same as the `softcrawl` console command."""

from studies.cli import main

raise SystemExit(main())
