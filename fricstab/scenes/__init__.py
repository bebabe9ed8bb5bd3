"""Scenes: particles, boundaries and the contact law of each studied system."""
