"""Offline demos: a recorded .viser file played with no server (core and views only)."""
