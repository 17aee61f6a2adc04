"""Shared test configuration: Hypothesis settings profiles.

Profiles (select one with the environment variable ``FAGORCNC_HYPOTHESIS_PROFILE``):

* ``default`` -- quick local runs (150 examples per property);
* ``ci``      -- CI runs (150 examples, derandomised so a run is reproducible);
  the default when the ``CI`` environment variable is set.  300 examples took the whole CI
  test run to 6 min on a 2-core machine of the fifteenth session (4 min 41 s with 150), over
  the 5-minute budget of the default run; the ``fuzz`` profile is where long budgets belong;
* ``fuzz``    -- long fuzzing sessions (20000 examples per property), e.g.
  ``FAGORCNC_HYPOTHESIS_PROFILE=fuzz pytest tests/test_fuzz.py tests/test_fast_path.py``.

No property test has a deadline: a parse of a whole program can take longer
than Hypothesis' default 200 ms on a loaded machine.
"""

from __future__ import annotations

import os

from hypothesis import settings

settings.register_profile("default", max_examples=150, deadline=None)
settings.register_profile("ci", max_examples=150, deadline=None, derandomize=True)
settings.register_profile("fuzz", max_examples=20000, deadline=None)

settings.load_profile(os.environ.get("FAGORCNC_HYPOTHESIS_PROFILE") or ("ci" if "CI" in os.environ else "default"))
