"""Planning: motion records -> jerk-limited timed segments -> sampled trajectory.

:class:`Trajectory` and :func:`sample` are imported on first use (PEP 562): ``fagorcnc check``
plans, it never samples.
"""

from typing import Any as _Any

from .. import _lazy
from .independent import IndependentSegment
from .planner import Planner, PlanningError, Segment, plan
from .segment import planning_code

#: names imported on first use: name -> the module that defines it
_LAZY = {"Trajectory": "fagorcnc.plan.trajectory", "sample": "fagorcnc.plan.trajectory"}


def __getattr__(name: str) -> _Any:
    """The names of :data:`_LAZY`, imported on first use and kept (PEP 562)."""
    return _lazy.attribute(globals(), _LAZY, name)


def __dir__() -> list[str]:
    """The module's names, the lazy ones included."""
    return _lazy.names(globals(), _LAZY)


__all__ = ["IndependentSegment", "Planner", "PlanningError", "Segment", "Trajectory", "plan", "planning_code", "sample"]
