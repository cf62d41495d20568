"""The progress line of Trainer.train: a bar redrawn in place on a terminal, one updating line in a
notebook, nothing when output goes to a file or a pipe (a log wants the callback's numbers)."""
import sys


def _in_notebook():
    shell = sys.modules.get("IPython")
    if shell is None:
        return False
    ip = shell.get_ipython() if hasattr(shell, "get_ipython") else None
    return ip is not None and type(ip).__name__ == "ZMQInteractiveShell"


def _clock(seconds):
    s = int(seconds)
    return "%d:%02d" % (s // 60, s % 60)


class Progress:
    """Draws report dicts (step, fraction, elapsed, loss, psnr) as one line."""

    def __init__(self, stream=None):
        self._stream = stream or sys.stderr
        self._notebook = _in_notebook()
        self._handle = None
        self._width = 0  # of the line drawn last: a shorter one is padded over it
        self.enabled = self._notebook or (hasattr(self._stream, "isatty") and self._stream.isatty())

    def line(self, r):
        frac = r.get("fraction", 0.0)
        eta = r["elapsed"] / frac - r["elapsed"] if frac > 0 else 0.0
        bar = int(frac * 20)
        text = "[%s%s] step %6d" % ("#" * bar, " " * (20 - bar), r["step"])
        if "loss" in r:
            text += "  loss %.5f  train PSNR %5.2f dB" % (r["loss"], r["psnr"])
        return text + "  %s elapsed  ETA %s" % (_clock(r["elapsed"]), _clock(eta))

    def update(self, r):
        if not self.enabled:
            return
        if self._notebook:
            from IPython.display import display

            if self._handle is None:
                self._handle = display({"text/plain": self.line(r)}, raw=True, display_id=True)
            else:
                self._handle.update({"text/plain": self.line(r)}, raw=True)
        else:
            text = self.line(r)
            self._stream.write("\r" + text.ljust(self._width))
            self._width = len(text)
            self._stream.flush()

    def close(self):
        if self.enabled and not self._notebook:
            self._stream.write("\n")
            self._stream.flush()
