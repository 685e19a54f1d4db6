"""Robots as data: one robot file (TOML) plus its URDF describe a robot to every part of kiloloop.

    robot = kl.Robot.load("ur5")                 # models/ur5/robot.toml
    robot = kl.Robot.load("path/to/my_arm.toml") # or a directory holding robot.toml
    robot = robot.with_overrides({"controller.bandwidth": 20.0})
    model = robot.model()                        # kl.RobotModel of the controlled chain

The file format is documented in docs/robots.md; the schema (every accepted key) in schema.py.
"""
from .robot_file import Robot, RobotFileError, resolve_robot_path  # noqa: F401
