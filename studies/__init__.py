"""Design studies, sweeps, the optimiser and the `softcrawl` command line.

`studies` sits on top of `geometry`, `fem` and `robot`; nothing below imports it.
"""
