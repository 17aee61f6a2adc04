"""Canned cycles of the 8060/8065 milling model (seed 002 L1447-L1487).

G80-G88, G98/G99, G160-G165 and G210-G212 expand into the ordinary motion records
(:mod:`fagorcnc.interp.records`) of the block that runs them, so the planner, the
envelope check, plots, back-ends and the cycle time see plain moves.

Modules: :mod:`.model` the modal cycle state, :mod:`.runner` the hook into the ISO
executor, one module per family (:mod:`.drilling` G81-G86, :mod:`.pockets` G87/G88,
:mod:`.milling` G210, :mod:`.threads` G211/G212,
:mod:`.patterns` G160-G165), :mod:`.variables` the V.C variables,
and :mod:`.choices`, every rule the sources leave open, in one place.
"""

from .model import CYCLE_CODES, PATTERN_CODES, ActiveCycle, CycleState
from .runner import CycleRunner

__all__ = ["CYCLE_CODES", "PATTERN_CODES", "ActiveCycle", "CycleRunner", "CycleState"]
