from __future__ import annotations

from pathlib import Path

import pytest

from twinlink.domain.errors import DocumentError
from twinlink.domain.yamlsource import dump_yaml, format_path, parse_yaml_stream

FIXTURES = Path(__file__).parent / "fixtures"


def test_timestamps_stay_text() -> None:
    [doc] = parse_yaml_stream("createdHuman: 2020-11-13T14:30:10.555Z\nday: 2020-11-13\n")
    assert doc.data == {"createdHuman": "2020-11-13T14:30:10.555Z", "day": "2020-11-13"}


def test_marks_point_at_keys_and_items() -> None:
    [doc] = parse_yaml_stream("a: 1\nlist:\n  - x: 2\n    y: 3\n")
    assert doc.where(("a",)) == (1, 1)
    assert doc.where(("list", 0, "y")) == (4, 5)
    assert doc.where(("list", 0, "missing")) == (3, 5)  # nearest ancestor


def test_stream_of_documents_is_indexed() -> None:
    docs = parse_yaml_stream("a: 1\n---\nb: 2\n---\nc: 3\n")
    assert [d.data for d in docs] == [{"a": 1}, {"b": 2}, {"c": 3}]
    assert [d.index for d in docs] == [0, 1, 2]


def test_unterminated_quote_of_published_example_names_its_line() -> None:
    text = (FIXTURES / "unterminated-quote.yaml").read_text()
    with pytest.raises(DocumentError) as caught:
        parse_yaml_stream(text)
    [problem] = caught.value.problems
    # The string opened on line 7 runs into line 8, where the parser sees the damage.
    assert problem.line == 8
    assert "nothing was stored" in caught.value.title


def test_error_in_second_document_says_which() -> None:
    with pytest.raises(DocumentError) as caught:
        parse_yaml_stream("a: 1\n---\nb: [1, 2\n")
    assert caught.value.problems[0].document == 1


def test_dump_keeps_key_order_and_unicode() -> None:
    out = dump_yaml({"z": 1, "a": "säätiö"})
    assert out.index("z:") < out.index("a:")
    assert "säätiö" in out


def test_format_path() -> None:
    assert format_path(("features", 2, "keywords", 0)) == "features[2].keywords[0]"
    assert format_path(()) == ""


def test_alias_bomb_is_refused_before_it_expands() -> None:
    lines = ["a0: &a0 [x, x, x, x, x, x, x, x, x, x]"]
    for i in range(1, 9):
        prev = f"*a{i - 1}"
        lines.append(f"a{i}: &a{i} [{', '.join([prev] * 10)}]")
    with pytest.raises(DocumentError, match="too large"):
        parse_yaml_stream("\n".join(lines) + "\n")


def test_deep_nesting_is_refused() -> None:
    # Older PyYAML recurses until RecursionError, 6.0.4 and later stop in the scanner: the
    # headline is the same either way.
    with pytest.raises(DocumentError, match="too deeply nested") as caught:
        parse_yaml_stream("a: " + "[" * 3000 + "]" * 3000 + "\n")
    assert caught.value.problems
