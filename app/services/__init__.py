"""Shared by every tab: the renderer, the robot catalogue, the symbolic workers, the classroom,
lifecycle and rate limits."""
