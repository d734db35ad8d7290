"""Each claim is keyed by the paper's statement, so that its key, its quote and its verdict read the same way.

The verdict is on the paper's statement ("the paper says ...: refuted"); a key naming our finding instead read
backwards beside it ("case2_has_no_limit_cycle refuted").  The report's table, the terminal table and
claims.json must all pair a statement with its own verdict.
"""

from __future__ import annotations

import re
import types

import frictionflow.cli.reproduce as cli_reproduce
from frictionflow.paper import evaluate
from frictionflow.paper.report import _claims_table

#: words that turn a statement into its opposite: in a key only where the paper's own sentence has them
NEGATIONS = {"no", "not", "never", "none", "nor", "without", "isnt", "doesnt", "cannot", "only"}

#: the keys that named our finding, not the paper's statement (each read backwards beside its verdict)
FINDING_KEYS = {
    "case1_vb_le_vd_is_rest_not_stick", "case2_has_no_limit_cycle", "case2_belt_speed_changes_cycle_size",
    "case2_belt_speed_is_not_only_a_phase", "case2_net_friction_sign_depends_on_window",
    "case2_paper_magnitudes_fix_the_window", "rc_halves_when_friction_doubles",
    "rc_falls_with_damping_at_the_papers_window", "rc_grows_with_belt_speed",
    "friction_dissipates_9999_percent_only_at_one_window", "trb_case2_is_one_in_steady_state",
    "trb_drops_with_damping_is_a_step_not_a_trend", "trb_belt_speed_matters_most_at_zeta_0",
}


def words(text: str) -> set[str]:
    return set(re.findall(r"[a-z0-9]+", text.lower().replace("'", "")))


def test_keys_are_unique_identifiers(data):
    keys = [c.key for c in evaluate(data)]
    assert len(keys) == len(set(keys)) == 21
    assert all(re.fullmatch(r"[a-z][a-z0-9_]*", k) for k in keys)


def test_no_key_names_our_finding(data):
    assert not FINDING_KEYS & {c.key for c in evaluate(data)}


def test_a_key_negates_only_what_the_paper_negates(data):
    for c in evaluate(data):
        extra = (set(c.key.split("_")) & NEGATIONS) - words(c.quote)
        assert not extra, (c.key, c.quote)


def test_the_limit_cycle_claim_reads_forwards(data):
    claims = {c.key: c for c in evaluate(data)}
    c = claims["case2_settles_on_a_limit_cycle"]
    assert "self-excited periodic vibrations in the steady state" in c.quote and c.verdict == "refuted"


def test_the_terminal_table_pairs_each_claim_with_its_verdict(data, monkeypatch, capsys):
    claims = evaluate(data)
    summary = types.SimpleNamespace(claims=claims, counts=lambda: "counts", report="report.html", files=[], seconds=1.0)
    monkeypatch.setenv("COLUMNS", "200")  # one row per claim, none wrapped
    cli_reproduce._print_summary(summary)
    text = capsys.readouterr().out
    assert "the paper's claim" in text and "our verdict on it" in text
    for c in claims:
        row = next(line for line in text.splitlines() if f" {c.key} " in line)
        assert re.search(rf"\b{c.verdict}\b", row) and c.figure in row


def test_the_report_pairs_each_quote_with_its_verdict(data):
    claims = evaluate(data)
    table = _claims_table(claims)
    rows = table.split("<tr>")[2:]
    assert len(rows) == len(claims)
    for c, row in zip(claims, rows):
        assert f'class="verdict {c.verdict}"' in row and c.quote[:40].replace("'", "&#x27;") in row
