"""``stages.summary_compare``: the cases of two studies whose results differ to their printed digits.

(``python -m benchmarks.simulate --compare-studies A B`` prints these lines; the tests use the package.)
"""

from stages.summary_compare import summary_differences

HEADER = "case_id,variant,L_F2,squeal,squeal_frequency,buildup_time,growth,runtime,L_W,L_pA\n"


def _study(folder, rows):
    folder.mkdir()
    (folder / "summary.csv").write_text("# summary.csv: a comment line\n" + HEADER + "".join(rows))
    return str(folder)


def test_only_changes_to_the_printed_digits_count(tmp_path):
    # case a: L_F2 -62.44 -> -62.41 prints -62.4 both times (not moved), the run time is not a
    # result; case b: its L_F2 moves at the printed digit and its frequency by 1 Hz (moved);
    # case c: only in B (counted)
    a = _study(tmp_path / "a", ["a-1234,base,-62.44,False,2243.2,,1.01,16.0,11.0,-12.4\n",
                                "b-5678,base,39.14,False,5042.0,,1.00,50.0,107.8,83.7\n"])
    b = _study(tmp_path / "b", ["a-1234,base,-62.41,False,2243.4,,1.01,12.0,11.0,-12.4\n",
                                "b-5678,base,39.16,False,5043.0,,1.00,40.0,107.8,83.7\n",
                                "c-9abc,base,1.0,False,203.0,,1.00,10.0,80.0,40.0\n"])
    lines, n_cases = summary_differences(a, b)
    assert len(lines) == 2 and n_cases == 3
    out = "\n".join(lines)
    assert "b: L_F2 39.1 -> 39.2; squeal_frequency 5042 -> 5043" in out
    assert "a:" not in out and "c: only in" in out
    assert summary_differences(a, a) == ([], 2)
