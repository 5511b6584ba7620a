#!/usr/bin/env python3
"""Batch throughput against one `combustion render` per job (docs/ci-rendering.md).

    python3 scripts/batch-throughput.py MANIFEST [RUNS]

Renders the manifest's jobs with `combustion batch` (one process, one device, each scene
uploaded once), then each job with its own `combustion render` process and the same
options (the jobs' `error` keys left out of both: render has no physics error), RUNS
times each (default 3), and prints the median wall-clock time and jobs per minute of
each. Uses target/debug/combustion (cargo build --profile test).
"""
import json, os, statistics, subprocess, sys, tempfile, time

BIN = os.path.join(os.path.dirname(__file__), "..", "target", "debug", "combustion")
OWN = {"name", "outputs", "criteria", "hdr_criteria", "error", "scene"}


def main():
    manifest_path = sys.argv[1]
    runs = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    folder = os.path.dirname(os.path.abspath(manifest_path))
    manifest = json.load(open(manifest_path))
    defaults = manifest.get("defaults", {})
    jobs = [{**defaults, **job} for job in manifest["jobs"]]
    for job in jobs:
        job.pop("error", None)
    work = tempfile.mkdtemp(prefix="combustion-throughput-")
    plain = dict(manifest, jobs=[{k: v for k, v in j.items()} for j in manifest["jobs"]])
    for job in plain["jobs"]:
        job.pop("error", None)
    plain.pop("$schema", None)
    plain_path = os.path.join(folder, ".throughput-manifest.json")
    json.dump(plain, open(plain_path, "w"))
    env = dict(os.environ, COMBUSTION_LOG="error")
    batch, single = [], []
    try:
        for run in range(runs):
            start = time.monotonic()
            subprocess.run([BIN, "batch", plain_path, "-o", os.path.join(work, f"batch-{run}")],
                           check=True, env=env, stdout=subprocess.DEVNULL)
            batch.append(time.monotonic() - start)
            start = time.monotonic()
            for job in jobs:
                scene = job["scene"]
                if not scene.startswith("builtin:"):
                    scene = os.path.join(folder, scene)
                args = [BIN, "render", scene]
                for key, value in job.items():
                    if key in OWN:
                        continue
                    if value is True:
                        value = "on" if key not in ("light-rig",) else None
                    args.append(f"--{key}" if value is None else f"--{key}={value}")
                outputs = job.get("outputs", ["png"])
                if "png" in outputs:
                    args += ["-o", os.path.join(work, f"{job['name']}-{run}.png")]
                if "exr" in outputs:
                    args += ["--hdr", os.path.join(work, f"{job['name']}-{run}.exr")]
                subprocess.run(args, check=True, env=env, stdout=subprocess.DEVNULL)
            single.append(time.monotonic() - start)
    finally:
        os.remove(plain_path)
    n = len(jobs)
    for label, times in (("batch (one process)", batch), ("render once per job", single)):
        median = statistics.median(times)
        print(f"{label}: {n} jobs, median {median:.1f} s of {runs} runs "
              f"({min(times):.1f}-{max(times):.1f} s), {60 * n / median:.0f} jobs per minute")


if __name__ == "__main__":
    main()
