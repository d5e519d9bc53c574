"""The one rule for a user's text on a terminal line (``errors.printable``), which the CLI's
messages and the dataset's log lines share."""

import unicodedata

import pytest

from forceclosure.errors import printable

#: Each character that could forge, colour, hide or reorder a line, by Unicode's own names.
DANGEROUS = {
    "\n": "LINE FEED", "\r": "CARRIAGE RETURN", "\t": "CHARACTER TABULATION",
    "\x1b": "ESCAPE", "\x00": "NULL", "\x7f": "DELETE", "\x85": "NEXT LINE",
    "\x9b": "CONTROL SEQUENCE INTRODUCER",
    "\u2028": "LINE SEPARATOR", "\u2029": "PARAGRAPH SEPARATOR",
    "\u202a": "LEFT-TO-RIGHT EMBEDDING", "\u202b": "RIGHT-TO-LEFT EMBEDDING",
    "\u202c": "POP DIRECTIONAL FORMATTING", "\u202d": "LEFT-TO-RIGHT OVERRIDE",
    "\u202e": "RIGHT-TO-LEFT OVERRIDE", "\u2066": "LEFT-TO-RIGHT ISOLATE",
    "\u2067": "RIGHT-TO-LEFT ISOLATE", "\u2068": "FIRST STRONG ISOLATE",
    "\u2069": "POP DIRECTIONAL ISOLATE",
}


@pytest.mark.parametrize("char", sorted(DANGEROUS))
def test_controls_separators_and_bidi_overrides_are_escaped(char):
    # the names (or, for controls without one, the aliases) say what each character is
    name = unicodedata.name(char, None) or DANGEROUS[char]
    assert name == DANGEROUS[char]
    code = ord(char)
    escape = "\\n" if char == "\n" else f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}"
    assert printable(f"name{char}.stl") == f"name{escape}.stl"


def test_lone_surrogates_are_escaped_and_plain_text_is_left_alone():
    assert printable("a\ud800b") == "a\\ud800b"
    text = "Fuß-大-é ✓ объект.stl"
    assert printable(text) == text
    assert printable("x" * 300, 10).startswith("xxxxxxxxxx") and "\n" not in printable(
        "x" * 300, 10)


def test_the_dataset_logs_with_the_same_rule(tmp_path):
    """A file whose name holds a right-to-left override and an escape fails to load; its log
    line shows both escaped (the dataset's own rule once let the override through)."""
    from forceclosure.datasets import Job, run, run_dataset

    assert run.printable is printable
    evil = tmp_path / "a\u202eltsx.\x1b[31m.stl"
    evil.write_bytes(b"solid nothing\n garbage \x00\n")
    lines: list[str] = []
    run_dataset([evil], tmp_path / "out", Job(contact="soft", mu=0.5, top=1), workers=1,
                progress=False, log=lines.append)
    failed = [line for line in lines if "failed" in line]
    assert len(failed) == 1, lines
    assert "a\\u202eltsx.\\x1b[31m.stl" in failed[0]
    assert not any(c in failed[0] for c in "\u202e\x1b\n")
