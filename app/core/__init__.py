"""The pure core: actions, state, the reducer and compute(state) → snapshot.

No viser, no threads, no clock.
"""
