"""A pyuvm environment for the contract ports of PMU 50 (docs/signals.md), with ``pmu50.Core`` as
the predictor and ``pmu50.Coverage`` as the coverage subscriber (docs/python.md, "UVM")."""
