"""Trainer.train's progress line: redrawn in place on a terminal, nothing into a file."""
import io

from vknerf._progress import Progress


class Terminal(io.StringIO):
    def isatty(self):
        return True


def test_a_terminal_gets_one_line_redrawn_in_place():
    out = Terminal()
    bar = Progress(out)
    assert bar.enabled
    bar.update({"step": 50, "fraction": 0.25, "elapsed": 3.0, "loss": 0.01, "psnr": 20.0})
    bar.update({"step": 100, "fraction": 0.5, "elapsed": 6.0})
    bar.close()
    first, second = out.getvalue().split("\r")[1:]
    assert first.startswith("[#####               ] step     50  loss 0.01000  train PSNR 20.00 dB  0:03 elapsed  ETA 0:09")
    assert second.startswith("[##########          ] step    100  0:06 elapsed  ETA 0:06")
    assert len(second) == len(first) + 1 and second.endswith(" \n")  # padded over the longer line, then a newline


def test_a_file_gets_nothing():
    out = io.StringIO()
    bar = Progress(out)
    bar.update({"step": 1, "fraction": 0.1, "elapsed": 1.0})
    bar.close()
    assert not bar.enabled and out.getvalue() == ""
