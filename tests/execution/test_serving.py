"""The child's loop (``registry/execution/serving.py``): every item answered as soon as
it is done, an exception or a result that cannot be sent back reported as text, and
the loop stops when the parent stops listening."""

from __future__ import annotations

from multiprocessing import Pipe

from registry.execution.serving import FAILURES, serve_items


def _call(item: str) -> object:
    if item == "raise":
        raise KeyError("k")
    if item == "lambda":
        return lambda: None  # cannot be pickled
    return item.upper()


def test_each_item_is_answered_in_turn():
    reader, writer = Pipe(duplex=False)
    assert serve_items(_call, ["a", "raise", "lambda", "b"], writer)
    got = [reader.recv() for _ in range(4)]
    assert got[0] == ("ok", "A") and got[3] == ("ok", "B")
    assert got[1] == ("error", "KeyError: 'k'")
    assert got[2][0] == "error" and got[2][1].startswith("result cannot be sent back: ")


def test_the_loop_stops_when_the_parent_stops_listening():
    reader, writer = Pipe(duplex=False)
    reader.close()
    assert serve_items(_call, ["a", "b"], writer) is False


def test_every_failure_kind_is_explained():
    assert set(FAILURES) == {"killed", "crashed", "error", "lost"}
    assert all(text for text in FAILURES.values())
