"""`python -m softcrawl` is the same as the `softcrawl` console command."""

from softcrawl.studies.cli import main

raise SystemExit(main())
