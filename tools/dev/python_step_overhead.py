"""What a Python training loop costs over `vknerf train` (docs/python.md): the same scene and
settings trained by the command line and by Python in turns, in one sitting. Two measures per
round: steps per second of wall time (compiling kernels left out of both: the CLI's elapsed time
excludes it, Python's clock starts after a first step), and CPU seconds per step (the process's
user + system time, lavapipe's threads included; the CLI's as the difference between a run of N
steps and one of 1, which removes loading and compiling), which a busy machine disturbs less.

    PYTHONPATH=build/python python3 tools/dev/python_step_overhead.py build/vknerf [--steps 300] [--rounds 2]
"""
import argparse
import re
import resource
import subprocess
import tempfile
import time

import vknerf


def cli_run(cli, scene, steps, out):
    """(steps per second, CPU seconds) of one `vknerf train` run."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run([cli, "train", scene, "--config", "fast", "--steps", str(steps), "--seed", "0",
                        "--save-every", "0", "-o", out], capture_output=True, text=True, check=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    m = re.search(r"after (\d+) steps \(([\d.]+) s", p.stdout)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return int(m.group(1)) / float(m.group(2)), cpu


def python_runs(ctx, data, steps):
    """{loop: (steps per second, CPU seconds per step)} over steps - 1 steps after a first one."""
    out = {}
    for name, run in (("step()", lambda t: [t.step() for _ in range(steps - 1)]),
                      ("step(read_loss=False)", lambda t: [t.step(read_loss=False) for _ in range(steps - 1)]),
                      ("train(steps=N)", lambda t: t.train(steps=steps - 1, progress=False))):
        trainer = vknerf.Trainer(ctx, data, vknerf.TrainConfig.fast(ctx, seed=0))
        trainer.step()  # compiles the kernels
        t0, c0 = time.perf_counter(), time.process_time()
        run(trainer)
        out[name] = ((steps - 1) / (time.perf_counter() - t0), (time.process_time() - c0) / (steps - 1))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("cli")
    ap.add_argument("--scene", default="assets/tabletop")
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--rounds", type=int, default=2)
    a = ap.parse_args()
    ctx = vknerf.Context()
    data = vknerf.Dataset.load(a.scene)
    with tempfile.TemporaryDirectory() as d:
        for r in range(a.rounds):
            rate, cpu_n = cli_run(a.cli, a.scene, a.steps, d + "/m.vknerf")
            _, cpu_1 = cli_run(a.cli, a.scene, 1, d + "/m1.vknerf")
            cli_cpu = (cpu_n - cpu_1) / (a.steps - 1)
            py = python_runs(ctx, data, a.steps)
            print(f"round {r + 1}: vknerf train {rate:.2f} steps/s, {1000 * cli_cpu:.1f} CPU ms/step; " +
                  "; ".join(f"{k} {v:.2f} steps/s ({100 * (rate - v) / rate:+.1f}%), {1000 * c:.1f} CPU ms/step "
                            f"({100 * (c - cli_cpu) / cli_cpu:+.1f}%)" for k, (v, c) in py.items()), flush=True)


if __name__ == "__main__":
    main()
