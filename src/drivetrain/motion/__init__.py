"""Motion: move profiles and cam laws, sampled as position, speed, acceleration and jerk over time."""
