"""The formal kit of the PMU 50 core (docs/hdl-guide.md section 6), as a package:

- common: the folders, the top's contract (hdl/formal/pmu50_contract.json), the parameter sets,
  file lists, running a tool, atomic writes, reading a VCD;
- aiger: AIGER models, cut per check;
- kit: the property kit (`hdl/formal/run.py`, `python -m pmu50_formal.kit`);
- coverage: the coverage proofs (`hdl/formal/coverage.py`, `python -m pmu50_formal.coverage`).

hdl/formal/run.py and hdl/formal/coverage.py are the commands; they run from hdl/formal, which
holds this package.
"""
