"""The claim verdicts and their numbers against those recorded before the refactor of issue 9."""

from __future__ import annotations

from tests.golden.outputs import claims_of
from tests.golden.test_golden import assert_same, golden


def test_claims_unchanged(data):
    assert_same(claims_of(data), golden("claims"), "claims")
