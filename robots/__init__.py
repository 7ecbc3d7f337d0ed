"""The Khepera-like robot: parameters, kinematics, the pymunk world, IR sensors and world files."""

from robots.params import KHEPERA, LONG_RANGE, SHORT_RANGE, RobotParams, SensorSet

__all__ = ["KHEPERA", "LONG_RANGE", "SHORT_RANGE", "RobotParams", "SensorSet"]
