"""What the memory benches share: one command under `/usr/bin/time -v`, its peak and wall time."""
import re
import subprocess
import sys


def measure(command):
    """Runs `command` under `/usr/bin/time -v`; returns (peak resident KiB, wall time text).

    Exits with the command's stderr when it fails.
    """
    run = subprocess.run(["/usr/bin/time", "-v", *command], capture_output=True, text=True)
    if run.returncode != 0:
        sys.exit(run.stderr)
    peak_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", run.stderr).group(1))
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)",
                     run.stderr).group(1)
    return peak_kb, wall
