"""The duty cycle: the motion at the motor shaft through every stage, with its torque metrics."""
