"""Small ``.tact`` documents built in the tests, with the Designer's structure (see
``tests/data/testfeedback.tact``)."""

import copy
import json

VEST_LAYOUT = [
    {"index": 4 * row + col, "x": [0, 0.333, 0.667, 1][col], "y": row * 0.25}
    for row in range(5)
    for col in range(4)
]
"""bHaptics' 4 x 5 vest panel: motor 0 top left, rows of four downwards."""


def point(x, y, intensity, time_ms):
    return {"x": x, "y": y, "intensity": intensity, "time": time_ms}


def path_mode(points, pattern="CONST_SPEED", fade="NONE"):
    return {
        "mode": "PATH_MODE",
        "dotMode": {"dotConnected": False, "feedback": []},
        "pathMode": {
            "feedback": [
                {
                    "playbackType": fade,
                    "movingPattern": pattern,
                    "visible": True,
                    "pointList": points,
                }
            ]
        },
    }


def dot_mode(dots, start_ms, end_ms, fade="NONE"):
    return {
        "mode": "DOT_MODE",
        "dotMode": {
            "dotConnected": False,
            "feedback": [
                {
                    "startTime": start_ms,
                    "endTime": end_ms,
                    "playbackType": fade,
                    "pointList": [{"index": i, "intensity": v} for i, v in dots],
                }
            ],
        },
        "pathMode": {"feedback": []},
    }


def effect(modes, start_ms=0, length_ms=1000):
    return {"name": "e", "startTime": start_ms, "offsetTime": length_ms, "modes": modes}


def document(*effects, tracks=None):
    """A file with ``effects`` on one track (or the given ``tracks``)."""
    return {
        "project": {
            "name": "test",
            "layout": {
                "type": "Tactot",
                "layouts": {"VestFront": VEST_LAYOUT, "VestBack": VEST_LAYOUT},
            },
            "tracks": tracks
            if tracks is not None
            else [{"enable": True, "effects": list(effects)}],
        },
        "durationMillis": 0,
        "intervalMillis": 20,
        "size": 20,
    }


def simple():
    """One CONST_SPEED path and one dot effect on the front."""
    return document(
        effect({"VestFront": path_mode([point(0, 1, 0.5, 0), point(1, 0, 1.0, 1000)])}),
        effect({"VestFront": dot_mode([(6, 0.8)], 100, 300)}, start_ms=200, length_ms=400),
    )


def crossing_paths_and_a_dot():
    """Two paths crossing the palm array corner to corner over 1 s, and the dot on motor 6
    (tactor (3, 4) on the palm array) from 0.3 to 0.5 s."""
    return document(
        effect({"VestFront": path_mode([point(0, 1, 0.5, 0), point(1, 0, 1.0, 1000)])}),
        effect({"VestFront": path_mode([point(0, 0, 1.0, 0), point(1, 1, 1.0, 1000)])}),
        effect({"VestFront": dot_mode([(6, 0.8)], 100, 300)}, start_ms=200, length_ms=400),
    )


def dots_only():
    """Dots alone, on both sides of the vest, as bHaptics' heartbeat files are: two effects, the
    first lighting motors 1 and 2 (intensity 1) from 0 to 0.1 s, the second motor 5 (0.5) from
    0.3 to 0.4 s."""
    beat = {"VestFront": dot_mode([(1, 1.0), (2, 1.0)], 0, 100),
            "VestBack": dot_mode([(1, 1.0), (2, 1.0)], 0, 100)}  # fmt: skip
    echo = {"VestFront": dot_mode([(5, 0.5)], 0, 100), "VestBack": dot_mode([(5, 0.5)], 0, 100)}
    return document(effect(beat, 0, 250), effect(echo, 300, 200))


def write(tmp_path, data, name="t.tact"):
    path = tmp_path / name
    path.write_text(json.dumps(data))
    return path


def mutate(data, where, value):
    """A deep copy of ``data`` with the field at ``where`` (a list of keys and indices) set to
    ``value``, or deleted when ``value`` is ``DELETE``."""
    out = copy.deepcopy(data)
    node = out
    for key in where[:-1]:
        node = node[key]
    if value is DELETE:
        del node[where[-1]]
    else:
        node[where[-1]] = value
    return out


DELETE = object()
