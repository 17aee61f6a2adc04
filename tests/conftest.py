"""Shared test configuration: Hypothesis settings profiles.

Profiles (select one with the environment variable ``FAGORCNC_HYPOTHESIS_PROFILE``):

* ``default`` -- quick local runs (150 examples per property);
* ``ci``      -- CI runs (300 examples, derandomised so a run is reproducible);
  the default when the ``CI`` environment variable is set;
* ``fuzz``    -- long fuzzing sessions (20000 examples per property), e.g.
  ``FAGORCNC_HYPOTHESIS_PROFILE=fuzz pytest tests/test_fuzz.py tests/test_fast_path.py``.

No property test has a deadline: a parse of a whole program can take longer
than Hypothesis' default 200 ms on a loaded machine.
"""

from __future__ import annotations

import os

from hypothesis import settings

settings.register_profile("default", max_examples=150, deadline=None)
settings.register_profile("ci", max_examples=300, deadline=None, derandomize=True)
settings.register_profile("fuzz", max_examples=20000, deadline=None)

settings.load_profile(os.environ.get("FAGORCNC_HYPOTHESIS_PROFILE") or ("ci" if "CI" in os.environ else "default"))
