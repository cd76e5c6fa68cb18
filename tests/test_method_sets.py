"""Experiments 1 and 3 on a chosen method set: balanced Latin square orders, the set kept in
the session, resumed only as it was, analysed as a study."""

import csv
import itertools
import json

import pytest

from tactile_core.experiments import Experiment1, Experiment3, SimulatedParticipant, open_session
from tactile_core.experiments.analysis import analyze, study_methods
from tactile_core.experiments.stats import ORDERS, williams_orders

SET = ["AS", "EN", "RO:r=1.5"]


@pytest.mark.parametrize("n", range(2, 9))
def test_williams_orders_are_balanced(n):
    orders = williams_orders(n)
    assert len(orders) == (n if n % 2 == 0 else 2 * n)
    letters = [chr(ord("A") + i) for i in range(n)]
    for order in orders:
        assert sorted(order) == letters
    # Every condition once in every position, as often as every other...
    for position in range(n):
        column = [o[position] for o in orders]
        assert {column.count(c) for c in letters} == {len(orders) // n}
    # ...and every condition right after every other equally often (first-order carry-over).
    follows = {pair: 0 for pair in itertools.permutations(letters, 2)}
    for order in orders:
        for a, b in itertools.pairwise(order):
            follows[(a, b)] += 1
    assert len(set(follows.values())) == 1


def test_williams_square_of_four_worked_by_hand():
    # first row 0, 1, 3, 2; each next row adds 1 mod 4.
    assert williams_orders(4) == ("ABDC", "BCAD", "CDBA", "DACB")


def run(folder, pid, index, methods, experiment=Experiment1, seed=1):
    session = open_session(folder, pid, seed=seed, index=index)
    runner = experiment(session, methods=methods)
    SimulatedParticipant(seed=index).run(runner)
    runner.close()
    return session


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def test_experiment1_on_a_set_rates_each_method_in_a_latin_square_order(tmp_path):
    orders = []
    for i in range(6):  # 3 methods: a square of 2 x 3 rows
        session = run(tmp_path, f"P{i}", i, ["as", "EN", "RO:r=1.50"])
        orders.append(session.orders["exp1"])
        data = json.loads(session.path.read_text())
        assert data["parameters"]["exp1_methods"] == SET
        got = rows(session.path.parent / "exp1.csv")
        assert len(got) == 1 + 2 * 3 * 3
        rated = [r["method"] for r in got if r["stage"] == "line" and r["property"] == "quality"]
        assert rated == [SET[ord(c) - ord("A")] for c in session.orders["exp1"]]
        assert sorted(got[0]["mapping"].split()) == sorted(SET)
    assert sorted(orders) == sorted(williams_orders(3))  # six participants: every row once


def test_the_papers_four_keep_the_papers_orders(tmp_path):
    session = run(tmp_path, "P0", 0, None)
    assert session.orders["exp1"] in ORDERS
    assert json.loads(session.path.read_text())["parameters"]["exp1_methods"] == [
        "CT", "MM", "AS", "IM"
    ]  # fmt: skip


def test_a_resume_with_another_set_is_refused_and_the_recorded_set_is_resumed(tmp_path):
    session = open_session(tmp_path, "P0", seed=1)
    runner = Experiment3(session, methods=SET)
    for _ in range(5):
        runner.answer(SimulatedParticipant(seed=0).respond(runner.current))
    runner.close()
    with pytest.raises(ValueError, match=r"methods AS IM differ from the session's AS EN RO"):
        Experiment3(open_session(tmp_path, "P0", seed=1), methods=["AS", "IM"])
    resumed = Experiment3(open_session(tmp_path, "P0", seed=1))  # the set from session.json
    assert resumed.methods == SET and resumed.done == 5 and resumed.total == 3 * 11
    resumed.close()


@pytest.mark.parametrize(
    "methods, message",
    [(["AS"], "2 to 8 different methods"), (["AS", "as"], "2 to 8 different methods"),
     (["AS", "NOPE"], "got 'NOPE'"), ("AS EN", "must be a list"),
     (["AS", "RO:r=99"], "method RO: r must be within")],
)  # fmt: skip
def test_a_bad_set_is_refused_by_name(tmp_path, methods, message):
    with pytest.raises(ValueError, match=message):
        Experiment1(open_session(tmp_path, "P0", seed=1), methods=methods)


def test_preparation_keys_follow_the_set(tmp_path):
    runner = Experiment1(open_session(tmp_path, "P0", seed=1), methods=SET)
    assert runner.current.options == ("1", "2", "3")
    assert runner.select(3).method in SET
    with pytest.raises(ValueError, match="key must be"):
        runner.select(4)
    runner.close()


def test_analysis_uses_the_studys_set_and_leaves_out_another(tmp_path):
    for i in range(4):
        run(tmp_path, f"P{i}", i, SET, Experiment3)
    run(tmp_path, "Q", 4, None, Experiment3)  # the paper's four: another set
    assert study_methods(tmp_path, "exp3") == (tuple(SET), ["Q"])
    lines = []
    result = analyze(tmp_path, out=lines.append)
    text = "\n".join(lines)
    assert "Experiment 3 (4 participants with all 3 sets)" in text
    assert "left out, another method set: Q" in text
    assert "multiplication by 3 for Bonferroni" in text  # 3 pairs
    assert set(result["exp3"]["table"]) == {("AS", "EN"), ("AS", "RO:r=1.5"), ("EN", "RO:r=1.5")}
    assert "Experiment 1" not in text  # nobody ran it
