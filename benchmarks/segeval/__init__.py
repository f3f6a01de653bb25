"""Evaluation oracles of the segmentation, kept out of the installed package.

- :mod:`segeval.evaluate`: hand–object contact events scored against the KIT bimanual
  clips' per-frame labels;
- :mod:`segeval.toolscore`: the KIT clips' tool–target pairs and their scoring;
- :mod:`segeval.reference`, :mod:`segeval.reference_comotion`: the per-frame Python
  reference of every detector (the same equations, one frame and one pair at a time).

The benchmarks import it as ``segeval`` (their folder is on ``sys.path`` when run as
``python benchmarks/x.py``); the tests put ``benchmarks/`` on the path in ``conftest.py``.
"""
