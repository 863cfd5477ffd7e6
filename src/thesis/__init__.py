"""Reproduction pipeline for Degrave (2018), chapters 2 to 7."""
