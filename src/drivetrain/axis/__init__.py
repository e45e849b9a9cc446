"""The axis model: the axis file read, validated and resolved into mechanism, stages, profile and motor."""
