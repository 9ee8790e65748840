"""The UCIS XML export (rtl_model/coverage/src/ucis.rs, `pmu50.export_ucis`) read back by pyucis.

Each export must be valid against the UCIS 1.0 schema (pyucis' copy of ucis.xsd), read by pyucis'
XML reader with every bin and its hits equal to coverage.json's, and two exports merged by
pyucis' merger must give the hits of `pmu50.merge_coverage` (the merge of `pmu50 merge`).
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from test_coverage import CONFIG, stimulus

# pyucis (python/requirements-dev.txt, installed into target/venv by `make python`)
from ucis.cover_type_t import CoverTypeT
from ucis.history_node_kind import HistoryNodeKind
from ucis.mem.mem_factory import MemFactory
from ucis.merge.db_merger import DbMerger
from ucis.scope_type_t import ScopeTypeT
from ucis.xml import validate_ucis_xml
from ucis.xml.xml_reader import XmlReader
from ucis.xml.xml_writer import XmlWriter

import pmu50

BINS = CoverTypeT.CVGBIN | CoverTypeT.IGNOREBIN | CoverTypeT.ILLEGALBIN


def ucis_hits(db) -> dict[str, int]:
    """Hits by coverage.json bin name, from the covergroup type scopes of a pyucis database
    (coverpoint `group.point`, bin `b` -> `group.point.b`; cross `c`, bin `<a,b>` ->
    `cross.c.a*b`)."""
    out: dict[str, int] = {}
    for inst in db.scopes(ScopeTypeT.INSTANCE):
        for cg in inst.scopes(ScopeTypeT.COVERGROUP):
            for cp in cg.scopes(ScopeTypeT.COVERPOINT):
                for b in cp.coverItems(BINS):
                    name = f"{cp.getScopeName()}.{b.getName()}"
                    assert name not in out, name
                    out[name] = b.getCoverData().data
            for cr in cg.scopes(ScopeTypeT.CROSS):
                for b in cr.coverItems(BINS):
                    a, c = b.getName().strip("<>").split(",")
                    name = f"cross.{cr.getScopeName()}.{a}*{c}"
                    assert name not in out, name
                    out[name] = b.getCoverData().data
    return out


def json_hits(path: Path) -> dict[str, int]:
    return {b["name"]: b["hits"] for b in json.loads(path.read_text())["bins"]}


@pytest.fixture(scope="module")
def runs(tmp_path_factory) -> tuple[Path, Path]:
    """Two coverage files of different lengths of the shared stimulus, and their UCIS exports."""
    d = tmp_path_factory.mktemp("ucis")
    out = []
    for name, n, verdict in (("a", 4000, "pass"), ("b", 9000, "fail")):
        core = pmu50.Core(**CONFIG)
        cov = pmu50.Coverage(core)
        for inp in stimulus(n):
            cov.step(core, **inp)
        cov.write(d / f"{name}.json", f"py/ucis/{name}", verdict)
        pmu50.export_ucis(d / f"{name}.json", d / f"{name}.xml")
        out.append(d / name)
    return out[0], out[1]


def test_export_is_valid_ucis_xml(runs):
    for r in runs:
        assert validate_ucis_xml(str(r.with_suffix(".xml")))


def test_pyucis_reads_every_bin_with_its_hits(runs):
    for r in runs:
        db = XmlReader().read(open(r.with_suffix(".xml")))
        want = json_hits(r.with_suffix(".json"))
        assert ucis_hits(db) == want
        assert sum(1 for v in want.values() if v) > 100
        nodes = list(db.historyNodes(HistoryNodeKind.ALL))
        assert [(n.getLogicalName(), n.getTestStatus()) for n in nodes] == [
            (f"py/ucis/{r.name}", r.name == "a")
        ]


def test_unreachable_bins_are_ignore_bins(runs):
    db = XmlReader().read(open(runs[0].with_suffix(".xml")))
    ignored = set()
    for inst in db.scopes(ScopeTypeT.INSTANCE):
        for cg in inst.scopes(ScopeTypeT.COVERGROUP):
            for cp in cg.scopes(ScopeTypeT.COVERPOINT):
                ignored |= {
                    f"{cp.getScopeName()}.{b.getName()}"
                    for b in cp.coverItems(CoverTypeT.IGNOREBIN)
                }
    declared = {n for n, kind, _, why in pmu50.Coverage.bins() if why and kind == "point"}
    assert ignored == declared and "fig18.history.both" in ignored


def test_pyucis_merge_equals_pmu50_merge(runs, tmp_path: Path):
    a, b = runs
    merged = tmp_path / "merged.json"
    pmu50.merge_coverage([a.with_suffix(".json"), b.with_suffix(".json")], merged)
    dbs = [XmlReader().read(open(r.with_suffix(".xml"))) for r in runs]
    out = MemFactory.create()
    DbMerger().merge(out, dbs)
    want = json_hits(merged)
    assert ucis_hits(out) == want
    assert want != json_hits(a.with_suffix(".json")), "the merge added something"
    # and pyucis' own XML of the merge reads back to the same numbers
    text = tmp_path / "merged.xml"
    with open(text, "w") as f:
        XmlWriter().write(f, out)
    assert ucis_hits(XmlReader().read(open(text))) == want
    # the export of pmu50's merge is the same database
    pmu50.export_ucis(merged, tmp_path / "pmu50_merged.xml")
    assert ucis_hits(XmlReader().read(open(tmp_path / "pmu50_merged.xml"))) == want


def test_export_is_deterministic_and_refuses_a_corrupt_file(runs, tmp_path: Path):
    a = runs[0]
    pmu50.export_ucis(a.with_suffix(".json"), tmp_path / "again.xml")
    assert (tmp_path / "again.xml").read_bytes() == a.with_suffix(".xml").read_bytes()
    bad = tmp_path / "bad.json"
    bad.write_text("[]")
    with pytest.raises(pmu50.CoverageError, match="bad.json"):
        pmu50.export_ucis(bad, tmp_path / "bad.xml")
    assert not (tmp_path / "bad.xml").exists()


def test_regression_shards_merged_by_pyucis_equal_pmu50_merge(tmp_path: Path):
    """`pmu50 regress` writes coverage.ucis.xml beside coverage.json: two shards' exports merged
    by pyucis give the coverage of `pmu50 merge` of the two shard folders."""
    from conftest import cli

    for i in (0, 1):
        cli(
            "regress",
            "--iterations",
            "24",
            "--shard",
            f"{i}/2",
            "--no-triage",
            "--out",
            str(tmp_path / f"s{i}"),
        )
    cli("merge", "--out", str(tmp_path / "m"), str(tmp_path / "s0"), str(tmp_path / "s1"))
    dbs = [XmlReader().read(open(tmp_path / f"s{i}" / "coverage.ucis.xml")) for i in (0, 1)]
    out = MemFactory.create()
    DbMerger().merge(out, dbs)
    want = json_hits(tmp_path / "m" / "coverage.json")
    assert ucis_hits(out) == want
    assert ucis_hits(XmlReader().read(open(tmp_path / "m" / "coverage.ucis.xml"))) == want
    assert validate_ucis_xml(str(tmp_path / "m" / "coverage.ucis.xml"))
