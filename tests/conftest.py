"""Test-wide settings.

Hypothesis' per-example deadline is off: CI machines have 2 cores shared by two
pytest workers, so wall-clock time per example is noise, not a property of the code.
Performance is measured by the scripts in benchmarks/, not by tests.
"""

from hypothesis import HealthCheck, settings

settings.register_profile(
    "oacdsl", deadline=None, suppress_health_check=[HealthCheck.too_slow], print_blob=True
)
settings.load_profile("oacdsl")
