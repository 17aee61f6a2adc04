"""Planning: motion records -> jerk-limited timed segments -> sampled trajectory."""

from .independent import IndependentSegment
from .planner import Planner, PlanningError, Segment, plan
from .segment import planning_code
from .trajectory import Trajectory, sample

__all__ = ["IndependentSegment", "Planner", "PlanningError", "Segment", "Trajectory", "plan", "planning_code", "sample"]
