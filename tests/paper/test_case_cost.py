"""The schedule's measured costs cover exactly the cases of the full run (a case added or
renamed without a cost would be scheduled by its kind's rough cost, possibly last)."""

from __future__ import annotations

from rotorsfd.paper.cases import select
from rotorsfd.paper.run import CASE_COST, case_cost


def test_every_case_of_the_full_run_has_a_measured_cost() -> None:
    names = {c.name for c in select(None)[1]}
    assert names == set(CASE_COST)
    assert all(v > 0 for v in CASE_COST.values())


def test_the_longest_case_is_scheduled_first() -> None:
    cases = select(None)[1]
    first = max(cases, key=case_cost)
    assert first.name == max(CASE_COST, key=CASE_COST.__getitem__) == "fig23-isola"
