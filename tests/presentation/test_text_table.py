"""The one plain-text table printer: columns as wide as their widest cell, two spaces
apart, a rule under the header, no trailing spaces; narrowed to a width by wrapping the
columns that may wrap; grouped under headings."""

from registry.presentation.text_table import grouped_table, text_table, wrapped


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


def test_a_table_that_fits_is_the_same_at_any_width():
    rows = [("euler", "verified"), ("yehia-b", "refuted")]
    assert text_table(("case", "verdict"), rows, width=20, wrap={1}) == text_table(
        ("case", "verdict"), rows
    )


def test_the_columns_that_may_wrap_narrow_until_the_table_fits():
    title = "Sur le probleme de la rotation d'un corps solide autour d'un point fixe"
    table = text_table(("case", "year", "title"), [("kovalevskaya-1889", 1889, title)], width=50)
    assert max(map(len, table.splitlines())) > 50  # no column may wrap: it stays wide
    table = text_table(
        ("case", "year", "title"), [("kovalevskaya-1889", 1889, title)], width=50, wrap={2}
    )
    lines = table.splitlines()
    assert max(map(len, lines)) <= 50
    assert lines[2].startswith("kovalevskaya-1889  1889  Sur le ")  # identifiers stay whole
    assert all(line.startswith(" " * 25) for line in lines[3:])  # the title's own column
    assert " ".join(line[25:] for line in lines[2:]) == title


def test_a_wrapping_column_keeps_eight_characters_and_breaks_a_longer_word():
    header = ("a", "authors", "t")
    table = text_table(
        header, [("x", "P. Birtea, I. Casu, D. Comanescu", "ok")], width=12, wrap={1}
    )
    lines = table.splitlines()
    assert lines[1] == "-  --------  --"  # the table cannot fit 12: authors keeps 8
    assert [line[3:].rstrip() for line in lines[2:]][-2:] == ["D. Coman", "escu"]


def test_an_equation_stays_on_one_line_and_a_word_breaks_after_a_hyphen():
    table = text_table(
        ("c", "holds when"),
        [("x", "nu = 0 or a1 = a3, a2 = a3 psi-gamma-grad-phi")],
        width=18,
        wrap={1},
    )
    cells = [line[3:] for line in table.splitlines()[2:]]
    assert "a2 = a3" in " | ".join(cells) and all(not c.endswith("=") for c in cells)
    assert "a2 = a3 psi-" in cells and "gamma-grad-phi" in cells


def test_a_grouped_table_aligns_its_columns_across_the_groups_under_their_headings():
    table = grouped_table(
        "case (family)",
        ("claim", "verdict"),
        [("euler (constant)", [("T", "verified"), ("M2", "verified")]), ("yehia-b", [])],
    )
    assert table.splitlines() == [
        "case (family)",
        "  claim  verdict",
        "  -----  --------",
        "euler (constant)",
        "  T      verified",
        "  M2     verified",
        "yehia-b",
    ]


def test_a_long_heading_wraps_with_its_next_lines_indented_twice():
    heading = "kovalevskaya-1889-heavy-top (version 1): Sur le probleme de la rotation"
    table = grouped_table("case", ("year",), [(heading, [("1889",)])], width=40)
    lines = table.splitlines()
    assert lines[3] == "kovalevskaya-1889-heavy-top (version 1):"
    assert lines[4] == "    Sur le probleme de la rotation"
    assert lines[5] == "  1889"
    assert max(map(len, lines)) <= 40


def test_wrapped_text_keeps_its_line_breaks_and_never_trails_spaces():
    text = wrapped("note: a b c\nsecond line", 10, indent="  ", subsequent="    ")
    assert text.splitlines() == ["  note: a", "    b c", "    second", "    line"]
    assert wrapped("one line", None, indent="  ") == "  one line"
