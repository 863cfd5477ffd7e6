"""Renders ``reports/<profile>/``: index.html, summary.md, per-table HTML, figures.

Only this package and :mod:`thesis.claims` import :mod:`thesis.paper`.
"""
