"""The one plain-text table printer: columns as wide as their widest cell, two spaces
apart, a rule under the header, no trailing spaces."""

from registry.presentation.text_table import text_table


def test_columns_are_padded_to_their_widest_cell():
    table = text_table(("a", "long header"), [("wide cell", "x"), ("y", "z")])
    assert table.splitlines() == [
        "a          long header",
        "---------  -----------",
        "wide cell  x",
        "y          z",
    ]


def test_cells_are_written_as_text_and_trailing_spaces_dropped():
    table = text_table(("n", "note"), [(1, ""), (22, "")])
    assert table.splitlines() == ["n   note", "--  ----", "1", "22"]
    assert all(line == line.rstrip() for line in table.splitlines())


def test_a_table_without_rows_is_its_header_and_rule():
    assert text_table(("case", "verdict"), []) == "case  verdict\n----  -------"
