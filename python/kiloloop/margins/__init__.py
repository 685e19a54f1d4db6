"""Stability margins of a loop of the closed SIL (`kiloloop margins`, docs/margins.md).

    op = operating_point(robot, settings)          # a scenario's rig, holding still, noise off
    a = analyse(op, "pitch")                       # both ways: injection and linearization
    a.margins.phase_margin_deg; a.margins.delay_margin_s; a.as_dict()

One module each: operating_point.py (the rig and fresh controllers), loops.py (which actuator
direction a loop is), injection.py (multi-sine in the native loop), linearization.py (MuJoCo's
transition matrices and the compiled controller differenced), frequency_response.py (margins from
L), analysis.py (both, compared), bode_plot.py, command.py (the command line's side).
"""
from __future__ import annotations

from .analysis import LoopAnalysis, analyse
from .frequency_response import Margins, margins
from .operating_point import operating_point

__all__ = ["LoopAnalysis", "Margins", "analyse", "margins", "operating_point"]
