"""The claims table of the report: every claim checked, and its verdict the one the numbers give."""

import re

from frictionflow.paper import evaluate
from frictionflow.paper.claims import VERDICTS

#: what the figure tests establish (test_fig2 ... test_band): the report must say the same
EXPECTED = {
    "case1_power_changes_sign": "supported",
    "case1_vb_le_vd_is_rest_not_stick": "refuted",
    "case1_periodic_self_excited": "supported",
    "case1_friction_input_equals_friction_dissipation": "supported",
    "case2_has_no_limit_cycle": "refuted",
    "case2_larger_damping_smaller_cycle": "partly",
    "case2_belt_speed_changes_cycle_size": "refuted",
    "case2_friction_level_leaves_damper_power": "supported",
    "case2_belt_speed_is_not_only_a_phase": "refuted",
    "case2_more_damping_less_power": "supported",
    "case2_net_friction_sign_depends_on_window": "refuted",
    "case2_paper_magnitudes_fix_the_window": "partly",
    "rc_halves_when_friction_doubles": "supported",
    "rc_falls_with_damping_at_the_papers_window": "refuted",
    "rc_grows_with_belt_speed": "refuted",
    "friction_dissipates_9999_percent_only_at_one_window": "partly",
    "trb_case1_falls_with_friction": "supported",
    "trb_case1_grows_with_belt_speed": "supported",
    "trb_case2_is_one_in_steady_state": "supported",
    "trb_drops_with_damping_is_a_step_not_a_trend": "partly",
    "trb_belt_speed_matters_most_at_zeta_0": "refuted",
}


def test_every_claim_gets_the_verdict_its_numbers_give(data):
    claims = {c.key: c for c in evaluate(data)}
    assert {k: c.verdict for k, c in claims.items()} == EXPECTED


def test_every_figure_has_claims_and_every_claim_has_numbers(data):
    claims = evaluate(data)
    assert {c.figure for c in claims} == {"fig2", "fig3", "fig4", "fig5", "fig6"}
    for c in claims:
        assert c.verdict in VERDICTS
        assert re.search(r"\d\.\d", c.evidence), c.key  # a measured number, not only words
        assert c.quote and "n/a" not in c.evidence, c.key
