"""Figures of the command line, with units on every axis."""
