"""Motion through J: inverse kinematics, resolved-rate control and redundancy."""
