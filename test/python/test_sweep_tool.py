"""kane_sim.sweep_tool, what `rosrun kane_sim sweep` runs, without a process: its own flags split
from simulate's, their hostile values, the rows written in case order whatever order the chunks
finish in, the progress line only on a terminal, and a local sweep's CSV equal to simulate's."""
import io
import subprocess

import pytest

from conftest import config_path, tool
from kane_sim import sweep_tool


def test_own_flags_are_split_from_simulates():
    own, rest = sweep_tool._split(["--duration", "1", "--chunk=8", "--scheduler", "tcp://h:1",
                                   "--sweep", "mechanism.gravity=1:2:2"])
    assert own == {"--chunk": "8", "--scheduler": "tcp://h:1"}
    assert rest == ["--duration", "1", "--sweep", "mechanism.gravity=1:2:2"]


@pytest.mark.parametrize("argv, words", [
    (["--chunk", "1", "--chunk", "2"], "--chunk given more than once"),
    (["--chunk"], "--chunk needs a value"),
    (["--scheduler", "--chunk", "3"], "needs a value, got the flag --chunk"),
])
def test_own_flags_refused_when_malformed(argv, words):
    with pytest.raises(sweep_tool.UsageError, match=words):
        sweep_tool._split(argv)


@pytest.mark.parametrize("text", ["nan", "inf", "-1", "0", "1e308", "", "abc", "١٢", "1.5"])
def test_hostile_numbers_are_refused_naming_the_flag(text):
    with pytest.raises(sweep_tool.UsageError, match="--chunk"):
        sweep_tool._whole("--chunk", text, 1, 100000)
    if text not in ("1.5",):
        with pytest.raises(sweep_tool.UsageError, match="--connect-timeout"):
            sweep_tool._seconds("--connect-timeout", text, 3600)


def test_arguments_refuse_cluster_flags_without_a_cluster():
    base = ["--config", config_path(), "--duration", "1", "--sweep", "mechanism.gravity=1:2:2"]
    assert sweep_tool.arguments(base)["chunk"] == 64
    for extra, words in ((["--chunk", "8"], "--chunk is for --scheduler"),
                         (["--scheduler", " "], "--scheduler needs"),
                         (["--scheduler", "tcp://h:1", "--jobs", "2"], "--jobs is this machine's")):
        with pytest.raises(sweep_tool.UsageError, match=words):
            sweep_tool.arguments(base + extra)
    with pytest.raises(sweep_tool.UsageError, match="give --sweep"):
        sweep_tool.arguments(["--duration", "1"])


class _Out:
    def __init__(self):
        self.text = ""

    def write(self, text):
        self.text += text


def test_rows_are_written_in_case_order_whatever_order_chunks_finish():
    rows = sweep_tool.Rows.__new__(sweep_tool.Rows)
    rows.out, rows.pending, rows.next, rows.name = _Out(), {}, 0, "test"
    rows.add(2, "c\n")
    rows.add(0, "a\n")
    assert rows.out.text == "a\n"  # chunk 1 still missing: chunk 2 waits
    rows.add(1, "b\n")
    assert rows.out.text == "a\nb\nc\n"
    rows.add(4, "e\n")
    rows.flush_rest()  # after a stop: what finished, in order
    assert rows.out.text == "a\nb\nc\ne\n"


class _Terminal(io.StringIO):
    def __init__(self, tty):
        super().__init__()
        self.tty = tty

    def isatty(self):
        return self.tty


def test_progress_only_on_a_terminal():
    for tty in (True, False):
        stream = _Terminal(tty)
        progress = sweep_tool.Progress(10, stream)
        progress.update(4)
        progress.finish()
        if tty:
            assert "sweep: 40.0 % (4 of 10 cases)" in stream.getvalue()
            assert stream.getvalue().endswith("\r\033[K")
        else:
            assert stream.getvalue() == ""


def test_a_local_sweep_writes_simulates_csv(tmp_path):
    args = ["--config", config_path(), "--duration", "0.5", "--torque", "2",
            "--sweep", "mechanism.spring_stiffness=100:300:5"]
    out = tmp_path / "sweep.csv"
    assert sweep_tool.run(sweep_tool.arguments(args + ["--csv", str(out)])) == 0
    simulated = subprocess.run([tool("simulate"), *args], capture_output=True, text=True,
                               check=True).stdout

    def without_wall_time(text):
        return [line.rsplit(",", 1)[0] for line in text.splitlines()]
    assert without_wall_time(out.read_text()) == without_wall_time(simulated)
