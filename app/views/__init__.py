"""What a tab draws: the panel (one module per tab) and the 3-D scene.

Views get ``dispatch``, never the session.
"""
