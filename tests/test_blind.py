"""Blind A/B as a session without a window (tactile_core.experiments.BlindSession): the mapping,
felt time on an injected clock, the ratings and their rules, the autosave and the saved file.

Nothing here sleeps: time is a virtual clock the tests advance. The expected mappings are dealt
here with ``random.Random(seed).shuffle``, the recipe docs/tuner.md gives for recovering an
autosave's mapping.
"""

import csv

import pytest

import tactile_core as tc
from tactile_core.device.host_clock import VirtualClock
from tactile_core.experiments import BlindSession, _blind_file
from tactile_core.experiments.blind import AUTOSAVE_COLUMNS, COLUMNS, shuffled
from tactile_core.rendering.scene import Scene

from .helpers import dealt

PAPER = ["CT", "MM", "AS", "IM"]


def read_rows(path):
    return list(csv.DictReader(path.read_text(encoding="utf-8").splitlines()))


@pytest.fixture
def clock():
    return VirtualClock()


@pytest.fixture
def session(clock, tmp_path):
    s = BlindSession(PAPER, clock=clock.now, autosave_dir=tmp_path / "autosave")
    s.scene = Scene(tc.Line((0.5, 1.84), (4.5, 4.16)), "AS", mu=0.3, gamma=0.6, duration_s=2.0)
    return s


def rate_all(session, key, value=50):
    for name in ("quality", "smoothness", "thickness"):
        session.rate(key, name, value)


# --- the mapping -------------------------------------------------------------------------------


@pytest.mark.parametrize("seed", [0, 1, 7, 2**31 - 1])
def test_shuffled_deals_the_methods_as_random_of_the_seed(seed):
    assert shuffled(PAPER, seed) == dealt(PAPER, seed)
    assert shuffled(("AS", "IM", "EN", "RO:r=1.5", "GS"), seed) == dealt(
        ("AS", "IM", "EN", "RO:r=1.5", "GS"), seed
    )


def test_start_deals_the_seeds_mapping_and_hides_it(session):
    assert not session.active and session.mapping == ()
    session.start(seed=7)
    assert list(session.mapping) == dealt(PAPER, 7)
    assert session.active and not session.revealed and session.seed == 7
    assert session.felt_s == (0.0,) * 4 and session.current_key is None
    assert all(session.rating(k, n) is None for k in range(1, 5)
               for n in ("quality", "smoothness", "thickness"))  # fmt: skip


def test_select_returns_the_method_behind_the_key(session):
    session.start(seed=3)
    assert [session.select(k) for k in (4, 1, 3, 2)] == [dealt(PAPER, 3)[k - 1]
                                                         for k in (4, 1, 3, 2)]  # fmt: skip
    assert session.current_key == 2


# --- felt time on the injected clock ------------------------------------------------------------


def test_felt_time_runs_only_while_a_key_plays(session, clock):
    session.start(seed=1)
    session.select(1)
    clock.advance(1.5)
    session.select(2)
    clock.advance(0.25)
    session.set_playing(False)  # paused: the clock runs on, felt time does not
    clock.advance(10.0)
    session.set_playing(True)
    clock.advance(0.5)
    assert session.felt_s == pytest.approx((1.5, 0.75, 0.0, 0.0), abs=1e-12)
    session.select(3, playing=False)  # selected, off
    clock.advance(3.0)
    assert session.felt_s == pytest.approx((1.5, 0.75, 0.0, 0.0), abs=1e-12)
    assert session.felt() == [True, True, False, False]


def test_a_key_selected_for_no_time_was_not_felt(session):
    session.start(seed=1)
    session.select(1)
    session.select(2)  # at once: key 1 was never felt
    assert session.felt() == [False, False, False, False]
    assert session.refusal("Reveal") == "Reveal: no key was felt yet"


def test_felt_time_stops_at_reveal(session, clock):
    session.start(seed=6)
    session.select(1)
    clock.advance(0.6)
    rate_all(session, 1)
    session.reveal()
    clock.advance(5.0)  # still playing after the reveal
    assert session.playing and session.felt_s == pytest.approx((0.6, 0.0, 0.0, 0.0))
    session.select(2)  # what is felt once the mapping is known is not blind
    clock.advance(2.0)
    assert session.felt_s == pytest.approx((0.6, 0.0, 0.0, 0.0))
    assert session.rows()[0]["felt_s"] == "0.60"


def test_the_clock_must_be_callable():
    with pytest.raises(ValueError, match=r"clock must be a callable.*12\.5"):
        BlindSession(PAPER, clock=12.5)


# --- ratings and the rules ----------------------------------------------------------------------


def test_reveal_and_save_need_every_felt_key_rated(session, clock, tmp_path):
    session.start(seed=2)
    for key in (3, 1):
        session.select(key)
        clock.advance(1.0)
    rate_all(session, 3, 70)
    session.rate(1, "quality", 40)
    assert session.missing() == ["key 1 smoothness", "key 1 thickness"]
    for action, call in (("Reveal", session.reveal),
                         ("Save", lambda: session.save(tmp_path / "r.csv"))):  # fmt: skip
        with pytest.raises(
            ValueError,
            match=f"{action} needs every key you felt rated: still "
            "empty: key 1 smoothness, key 1 thickness",
        ):
            call()
    assert session.active and not (tmp_path / "r.csv").exists()
    rate_all(session, 1, 40)
    session.reveal()
    assert session.revealed and not session.active


def test_a_key_never_played_saves_as_not_rated(session, clock, tmp_path):
    session.start(seed=3)
    for key in (1, 2):
        session.select(key)
        clock.advance(0.5)
        rate_all(session, key, 60)
    with pytest.raises(ValueError, match="key 3 was not played"):
        session.rate(3, "quality", 50)  # nothing to rate yet: it would pass for a rating
    path = session.save(tmp_path / "b.csv")
    rows = read_rows(path)
    assert [r["felt"] for r in rows] == ["1", "1", "0", "0"]
    assert [r["felt_s"] for r in rows] == ["0.50", "0.50", "0.00", "0.00"]
    assert rows[2]["quality"] == rows[3]["thickness"] == ""  # not rated, not 50


def test_not_rated_is_distinct_from_zero(session, clock, tmp_path):
    session.start(seed=4)
    session.select(1)
    clock.advance(1.0)
    rate_all(session, 1, 0)
    assert session.rating(1, "quality") == 0 and session.missing() == []
    session.rate(1, "quality", None)  # cleared again
    assert session.missing() == ["key 1 quality"]
    session.rate(1, "quality", 0)
    row = read_rows(session.save(tmp_path / "z.csv"))[0]
    assert (row["quality"], row["smoothness"], row["thickness"]) == ("0", "0", "0")
    assert read_rows(tmp_path / "z.csv")[1]["quality"] == ""


@pytest.mark.parametrize(
    ("key", "name", "value", "said"),
    [
        (1, "quality", 101, "quality of key 1 must be >= 0 and <= 100, got 101"),
        (1, "smoothness", -1, "smoothness of key 1 must be >= 0 and <= 100, got -1"),
        (1, "quality", 50.5, "quality of key 1 must be an integer, got 50.5"),
        (1, "quality", True, "quality of key 1 must be an integer, got True"),
        (1, "quality", "50", "quality of key 1 must be an integer"),
        (1, "colour", 50, "name must be one of"),
        (5, "quality", 50, "key must be >= 1 and <= 4, got 5"),
    ],
)
def test_bad_ratings_are_refused_by_name(session, clock, key, name, value, said):
    session.start(seed=1)
    session.select(1)
    clock.advance(1.0)
    with pytest.raises(ValueError, match=said):
        session.rate(key, name, value)
    assert not session.unsaved


def test_nothing_is_rated_before_a_session(session):
    with pytest.raises(ValueError, match="no blind A/B session"):
        session.rate(1, "quality", 50)
    with pytest.raises(ValueError, match="no blind A/B session"):
        session.select(1)


@pytest.mark.parametrize(
    ("methods", "said"),
    [
        (["AS"], "2 to 8 distinct methods"),
        (["AS", "AS"], "2 to 8 distinct methods"),
        (["AS", "IM", "CT", "MM", "EN", "RO", "GS", "PK", "BA"], "2 to 8 distinct methods"),
        (["AS", "XX"], "XX"),
        ("AS IM", "methods must be a list"),
        ([1, 2], "methods must be method names"),
    ],
)
def test_bad_method_sets_are_refused(methods, said):
    with pytest.raises(ValueError, match=said):
        BlindSession(methods)


def test_methods_cannot_change_during_a_session_or_with_unsaved_ratings(session, clock, tmp_path):
    session.start(seed=1)
    with pytest.raises(ValueError, match="blind A/B is running"):
        session.set_methods(["AS", "IM"])
    session.select(1)
    clock.advance(1.0)
    rate_all(session, 1)
    session.reveal()
    with pytest.raises(ValueError, match="not saved"):
        session.set_methods(["AS", "IM"])
    session.save(tmp_path / "r.csv")
    session.set_methods(["AS", "IM"])
    assert session.methods == ("AS", "IM") and session.mapping == ()


# --- never lost without a word ------------------------------------------------------------------


def test_ratings_are_autosaved_as_they_are_entered(session, clock, tmp_path):
    session.start(seed=9)
    session.select(1)
    clock.advance(1.0)
    session.rate(1, "smoothness", 33)
    path = session.autosave_path
    assert path.parent == tmp_path / "autosave" and path.name.endswith("-seed9.csv")
    rows = read_rows(path)
    assert tuple(rows[0]) == AUTOSAVE_COLUMNS
    assert rows[0]["smoothness"] == "33" and rows[0]["quality"] == ""
    assert all(r["method"] == "" for r in rows)  # the file does not give the mapping away
    assert rows[0]["methods"] == "CT MM AS IM" and rows[0]["seed"] == "9"
    assert rows[0]["shape"] == "line:0.5,1.84,4.5,4.16" and rows[0]["mu"] == "0.3"
    rate_all(session, 1)
    session.reveal()
    assert [r["method"] for r in read_rows(path)] == dealt(PAPER, 9)
    session.save(tmp_path / "ratings.csv")
    assert not path.exists()  # saved: the autosave has done its work


def test_a_failed_autosave_keeps_the_rating_and_the_previous_file(session, clock, monkeypatch):
    session.start(seed=9)
    session.select(1)
    clock.advance(1.0)
    session.rate(1, "quality", 10)
    before = session.autosave_path.read_text()

    def full_disk(f, rows, *, header):
        f.write("session,key")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(_blind_file, "write_rows", full_disk)
    session.rate(1, "quality", 20)
    assert session.rating(1, "quality") == 20 and session.unsaved
    assert "could not autosave the ratings" in session.autosave_error
    assert "No space left" in session.autosave_error
    assert session.autosave_path.read_text() == before  # written atomically: never half a file
    assert [p.name for p in session.autosave_path.parent.iterdir()] == [session.autosave_path.name]


def test_start_over_unsaved_ratings_needs_discard(session, clock):
    session.start(seed=2)
    session.select(1)
    clock.advance(1.0)
    session.rate(1, "quality", 70)
    first = session.autosave_path
    with pytest.raises(ValueError, match=r"not saved .*autosaved in .*discard=True"):
        session.start(seed=5)
    assert session.seed == 2 and session.rating(1, "quality") == 70
    session.start(seed=5, discard=True)
    assert session.rating(1, "quality") is None and session.seed == 5
    assert read_rows(first)[0]["quality"] == "70"  # still on disk


def test_cancel_gives_back_the_scene_from_before_only_while_blind(session, clock):
    before = session.scene
    session.start(seed=4)
    session.scene = before.replace(method="IM")  # what key 1 played
    session.start(seed=8)  # a reshuffle keeps the scene from before the first
    session.select(2)
    clock.advance(0.3)
    session.rate(2, "quality", 40)
    assert session.cancel() is before
    assert session.mapping == () and not session.unsaved
    assert read_rows(session.autosave_path)[1]["quality"] == "40"  # kept in the autosave
    session.start(seed=1)
    session.select(1)
    clock.advance(1.0)
    rate_all(session, 1)
    session.reveal()
    assert session.cancel() is None  # revealed: nothing hidden to put back


def test_save_appends_with_one_header_and_refuses_other_columns(session, clock, tmp_path):
    session.start(seed=7)
    session.select(1)
    clock.advance(1.0)
    rate_all(session, 1, 80)
    out = tmp_path / "blind.csv"
    session.save(out)
    session.reveal()
    session.save(out)
    rows = read_rows(out)
    assert tuple(rows[0]) == COLUMNS and len(rows) == 8
    assert [r["method"] for r in rows[:4]] == dealt(PAPER, 7)
    assert [r["revealed_before_save"] for r in (rows[0], rows[4])] == ["False", "True"]
    other = tmp_path / "other.csv"
    other.write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="holds other columns"):
        session.save(other)
    assert other.read_text() == "a,b\n1,2\n"
    with pytest.raises(ValueError, match=r"must end in \.csv"):
        session.save(tmp_path / "r.txt")


def test_listeners_hear_each_change(session, clock):
    heard = []
    session.listeners.append(lambda: heard.append(session.current_key))
    session.start(seed=1)
    session.select(2)
    clock.advance(1.0)
    session.rate(2, "quality", 5)
    session.rate(2, "quality", 5)  # no change: nothing to hear
    session.set_playing(False)
    assert heard == [None, 2, 2, 2]


# --- autosaves written by the tuner 0.2 ---------------------------------------------------------

OLD_AUTOSAVE = """\
session,key,method,felt,felt_s,quality,smoothness,thickness,shape,mu,gamma,duration_s,pause_s,\
seed,revealed_before_save,methods
2025-03-04T10:11:12,1,,1,3.20,70,55,,"line:0.5,1.8,4.5,4.2",0.33,0.7,2.0,0.5,1234,False,CT MM AS IM
2025-03-04T10:11:12,2,,1,1.05,,,,"line:0.5,1.8,4.5,4.2",0.33,0.7,2.0,0.5,1234,False,CT MM AS IM
2025-03-04T10:11:12,3,,0,0.00,,,,"line:0.5,1.8,4.5,4.2",0.33,0.7,2.0,0.5,1234,False,CT MM AS IM
2025-03-04T10:11:12,4,,0,0.00,,,,"line:0.5,1.8,4.5,4.2",0.33,0.7,2.0,0.5,1234,False,CT MM AS IM
"""
"""An autosave as the tuner 0.2 wrote it (csv quotes the shape's commas)."""


def _old_autosave(tmp_path):
    path = tmp_path / "blind-ab-2025-03-04T101112-seed1234.csv"
    path.write_text(OLD_AUTOSAVE, encoding="utf-8")
    return path


def test_an_autosave_of_the_tuner_0_2_loads_with_its_mapping_recovered(tmp_path, clock):
    path = _old_autosave(tmp_path)
    session = BlindSession.from_autosave(path, clock=clock.now)
    assert list(session.mapping) == dealt(PAPER, 1234) and session.seed == 1234
    assert session.active and session.unsaved and session.autosave_path == path
    assert session.felt_s == pytest.approx((3.2, 1.05, 0.0, 0.0))
    assert (session.rating(1, "quality"), session.rating(1, "thickness")) == (70, None)
    assert session.missing() == ["key 1 thickness", "key 2 quality", "key 2 smoothness",
                                 "key 2 thickness"]  # fmt: skip
    session.rate(1, "thickness", 20)  # goes on in the same file
    rows = read_rows(path)
    assert rows[0]["thickness"] == "20" and rows[0]["shape"] == "line:0.5,1.8,4.5,4.2"
    assert rows[0]["session"] == "2025-03-04T10:11:12" and rows[0]["method"] == ""


@pytest.mark.parametrize(
    ("change", "said"),
    [
        (lambda t: t.replace(",seed,", ",seed_,"), "not a blind A/B autosave"),
        (lambda t: t.replace("3.20", "-3"), "felt_s of key 1"),
        (lambda t: t.replace(",70,", ",170,"), "quality of key 1"),
        (lambda t: t.rsplit("\n", 2)[0] + "\n", "one row per key 1-4"),
        (lambda t: t.replace("T10:11:12,1,,", "T10:11:12,1,XX,"), "do not follow from its seed"),
    ],
)
def test_a_damaged_autosave_is_refused_naming_the_file(tmp_path, change, said):
    path = _old_autosave(tmp_path)
    path.write_text(change(path.read_text()))
    with pytest.raises(ValueError, match=said) as info:
        BlindSession.from_autosave(path)
    assert str(path) in str(info.value)
