"""Reproduction pipeline for Degrave (2018), chapters 2 to 7."""

from thesis import cpupins as _cpupins

# before anything imports numpy: numpy and OpenBLAS pick their CPU code paths when they load
_cpupins.pin()
