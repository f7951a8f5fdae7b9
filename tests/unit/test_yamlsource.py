from __future__ import annotations

from pathlib import Path

import pytest

from twinlink.domain.errors import DocumentError
from twinlink.domain.jsontext import int64_problem
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


# -- keys given twice, integers Python cannot read ------------------------------------------


def test_a_key_given_twice_is_refused_at_its_second_place() -> None:
    text = "version: '1.0'\nfeatures:\n  - name: a\n    description: x\n    name: b\nname: t\n"
    with pytest.raises(DocumentError, match="given twice") as caught:
        parse_yaml_stream(text)
    [problem] = caught.value.problems
    assert (problem.line, problem.column, problem.path) == (5, 5, "features[0].name")
    assert problem.message.startswith("key 'name' is given twice in one mapping")
    assert "first at line 3, column 5" in problem.message
    assert "nothing was stored" in caught.value.title


def test_every_key_given_twice_is_reported_once_even_through_aliases() -> None:
    text = "a: &m {x: 1, x: 2}\nb: *m\nc: 1\nc: 2\n---\nd: 1\nd: 1\n"
    with pytest.raises(DocumentError) as caught:
        parse_yaml_stream(text)
    # The first document stops the stream; its two keys are named once each.
    assert [(p.line, p.path, p.document) for p in caught.value.problems] == [
        (1, "a.x", 0),
        (4, "c", 0),
    ]


def test_merged_keys_may_be_overridden_and_text_and_numbers_are_different_keys() -> None:
    text = "base: &b {unit: m, min: 0}\nsignal:\n  <<: *b\n  min: 1\n1: number\n'1': text\n"
    [doc] = parse_yaml_stream(text)
    assert doc.data["signal"] == {"unit": "m", "min": 1}
    assert doc.data[1] == "number" and doc.data["1"] == "text"


@pytest.mark.parametrize("literal", ["7" * 5000, "-" + "1" * 4301, "1" + ":30" * 100_000])
def test_an_integer_python_will_not_read_is_refused_with_its_line(literal: str) -> None:
    with pytest.raises(DocumentError) as caught:
        parse_yaml_stream(f"a: 1\nb:\n  - {literal}\n")
    [problem] = caught.value.problems
    assert (problem.line, problem.column) == (3, 5)
    assert "does not fit in 64 bits" in problem.message
    assert problem.message == int64_problem(literal)
    assert len(problem.message) < 200
