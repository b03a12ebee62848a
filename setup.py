"""The package layout, which pyproject.toml alone cannot state: one import name, `softcrawl`.

The folder softcrawl/ is the package root (the public API, the analytic models, the materials);
the requested top-level folders fem/, geometry/ and studies/ install as its subpackages
softcrawl.fem, softcrawl.geometry and softcrawl.studies. Nothing else enters site-packages.
Everything else (metadata, dependencies, the command) is in pyproject.toml.
"""

from setuptools import find_packages, setup

#: Subpackage -> the top-level folder that holds it.
MAPPED = {"softcrawl.fem": "fem", "softcrawl.geometry": "geometry", "softcrawl.studies": "studies"}

packages = find_packages(include=["softcrawl", "softcrawl.*"])
for name, folder in MAPPED.items():
    packages += [name, *(f"{name}.{sub}" for sub in find_packages(folder))]
setup(packages=packages, package_dir=dict(MAPPED))
