"""Shipped tensile test data (see README.md for attribution and licence).

A package so that setuptools ships the CSVs."""
