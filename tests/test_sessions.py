"""A participant's session on disk: ids that are safe folder names, recruitment indices that
never repeat another participant's orders, and parameters (Exp. 3's emphasis and method set)
fixed by the first answer, not before, and never by a copy the lock refused."""

import json
import shutil

import pytest

from tactile_core.experiments import RUNNERS
from tactile_core.experiments.results import SESSION_FILE, check_participant, open_session


@pytest.mark.parametrize("pid", ["P1\n", "P1 ", "", "a" * 65, "../x", "P1/2"])
def test_participant_ids_are_strict(pid):
    with pytest.raises(ValueError, match="participant"):
        check_participant(pid)


def test_a_copy_refused_the_participant_writes_nothing_to_their_session(tmp_path):
    # Exp. 3's emphasis and method set were saved before the lock was taken: a second copy,
    # refused, had already rewritten session.json, and Exp. 3 was then refused with the
    # participant's real emphasis ("differs from the session's 0.5").
    first = RUNNERS["exp2"](open_session(tmp_path, "P01"))
    try:
        path = tmp_path / "participant-P01" / SESSION_FILE
        before = path.read_bytes()
        with pytest.raises(Exception, match="being recorded by"):
            RUNNERS["exp3"](open_session(tmp_path, "P01"), emphasis=0.5, methods=["CT", "MM"])
        assert path.read_bytes() == before
        assert "exp3_emphasis" not in json.loads(before).get("parameters", {})
    finally:
        first.close()
    third = RUNNERS["exp3"](open_session(tmp_path, "P01"), emphasis=0.0)
    third.close()  # the participant's own emphasis, accepted


def test_a_deleted_participant_does_not_give_the_next_one_anothers_orders(tmp_path):
    for pid in ("P01", "P0l", "P02"):  # a typo among them, deleted afterwards
        open_session(tmp_path, pid)
    shutil.rmtree(tmp_path / "participant-P0l")
    assert open_session(tmp_path, "P03").index == 3  # was 2, P02's: the same orders
    assert open_session(tmp_path, "P02").index == 2


def test_a_run_stopped_before_its_first_answer_may_start_again_otherwise(tmp_path):
    # A mistyped method set or emphasis, started and stopped at once, could only be undone
    # with a new participant id (and so another recruitment index).
    wrong = RUNNERS["exp3"](open_session(tmp_path, "P01"), emphasis=0.5, methods=["CT", "MM"])
    wrong.close()  # no answer
    paper = ["CT", "MM", "AS", "IM"]
    right = RUNNERS["exp3"](open_session(tmp_path, "P01"), emphasis=0.0, methods=paper)
    assert right.methods == ["CT", "MM", "AS", "IM"] and right.emphasis == 0.0
    right.answer("continue", rt_s=0.5)  # the first screen: now an answer is recorded
    right.close()
    session = json.loads((tmp_path / "participant-P01" / SESSION_FILE).read_text())
    assert session["parameters"]["exp3_emphasis"] == 0.0
    assert session["parameters"]["exp3_methods"] == ["CT", "MM", "AS", "IM"]
    with pytest.raises(ValueError, match=r"emphasis 0\.5 differs from the session.s 0"):
        RUNNERS["exp3"](open_session(tmp_path, "P01"), emphasis=0.5)
