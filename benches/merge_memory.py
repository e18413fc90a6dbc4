#!/usr/bin/env python3
"""Peak memory of `udc-studio sweep merge` on a million rows (the Limits chapter's figure).

Builds two shard folders of 500 000 rows each from a real 8-point sweep's manifest and rows
(tests/sweep/tiny.toml; points renumbered, hashes made unique), then times the merge under
`/usr/bin/time -v`. Usage: benches/merge_memory.py [BINARY] [ROWS]; the default binary is
target/release/udc-studio.
"""
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
binary = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "target/release/udc-studio")
rows = int(sys.argv[2]) if len(sys.argv) > 2 else 1_000_000

with tempfile.TemporaryDirectory() as tmp:
    template = os.path.join(tmp, "template")
    subprocess.run(
        [binary, "sweep", os.path.join(ROOT, "tests/sweep/tiny.toml"), "--out", template,
         "--quiet", "--no-plots"],
        check=True,
    )
    manifest = json.load(open(os.path.join(template, "sweep.json")))
    lines = open(os.path.join(template, "results.csv")).read().splitlines()
    header, body = lines[0], [l.split(",") for l in lines[1:]]
    manifest["points"] = rows
    manifest["rows"] = rows // 2
    manifest["complete"] = False
    shards = []
    for s in range(2):
        d = os.path.join(tmp, f"s{s}")
        os.makedirs(d)
        m = dict(manifest, shard=[s, 2])
        json.dump(m, open(os.path.join(d, "sweep.json"), "w"))
        with open(os.path.join(d, "results.csv"), "w") as f:
            f.write(header + "\n")
            # Completion order, as a sweep writes: interleaved, not sorted.
            for p in list(range(s, rows, 2))[::-1]:
                r = list(body[p % len(body)])
                r[0] = str(p)
                r[1] = f"{p:032x}"
                f.write(",".join(r) + "\n")
        shards.append(d)
    out = os.path.join(tmp, "merged")
    run = subprocess.run(
        ["/usr/bin/time", "-v", binary, "sweep", "merge", *shards, "--out", out, "--quiet",
         "--no-plots"],
        capture_output=True, text=True,
    )
    if run.returncode != 0:
        sys.exit(run.stderr)
    peak_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", run.stderr).group(1))
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", run.stderr)
    merged = sum(1 for _ in open(os.path.join(out, "results.csv"))) - 1
    print(f"sweep merge of {rows} rows in 2 shards: peak {peak_kb / 1024:.0f} MiB, "
          f"wall {wall.group(1)}, {merged} rows written")
