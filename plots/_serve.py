"""Runs plot scripts one after another in this one interpreter, for `sglab reproduce`: the
interpreter's start and `import matplotlib` (about 0.35 CPU s each) are paid once per run instead
of once per figure script.

Reads one request per line on the socket at file descriptor 3, a JSON array: the script and its
arguments, as `python3 SCRIPT ARGS…` would get them. Runs the script as __main__ with that
sys.argv, then answers with one line on the same socket, a JSON object: "status" (the exit status
`python3 SCRIPT ARGS…` would have had), "cpu" (this process's and its finished children's CPU
seconds, such as a script's worker pool, while the script ran) and "wrote" (the absolute path of
every file the script wrote through _common's temporary-file-and-rename, its worker processes'
included: what the step's marker records as its outputs, since several interpreters may write into
one figure directory at the same time). The scripts keep stdout and stderr; stdin is /dev/null.
Between two scripts every figure is closed and matplotlib's settings are restored to those read at
start, so each script starts as it would in a fresh interpreter. Ends when the other side stops sending.
usage: _serve.py   (requests and answers on the socket at fd 3)
"""
import fcntl
import json
import os
import resource
import runpy
import socket
import sys
import tempfile
import traceback

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import _common  # noqa: E402  (this directory's: the scripts import the same module object)

_REPLACE = _common._replace


def _recorded_replace(path, write):
    """_common._replace, which also appends the path written to the current script's record: a
    file opened for appending, which the script's worker processes (forked by multiprocessing)
    inherit and append to as well, one write per path."""
    result = _REPLACE(path, write)
    if _record is not None:
        os.write(_record, (json.dumps(os.path.abspath(os.fspath(path))) + "\n").encode())
    return result


_common._replace = _recorded_replace
_record = None  # the current script's record of written paths (a descriptor opened O_APPEND)


def cpu_seconds():
    own, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def exit_status(code):
    """The status of `python3` ending with SystemExit(code)."""
    if code is None:
        return 0
    if isinstance(code, int):
        return code & 0xFF
    print(code, file=sys.stderr)
    return 1


def run(argv):
    """Runs argv[0] as __main__ with sys.argv = argv; returns its exit status."""
    script = os.path.abspath(argv[0])
    saved_argv, saved_path0 = sys.argv, sys.path[0]
    sys.argv = list(argv)
    sys.path[0] = os.path.dirname(script)
    try:
        runpy.run_path(script, run_name="__main__")
        return 0
    except SystemExit as e:
        return exit_status(e.code)
    except BaseException:  # noqa: B902 - reported as `python3 SCRIPT` reports it, status 1
        traceback.print_exc()
        return 1
    finally:
        sys.argv, sys.path[0] = saved_argv, saved_path0
        plt.close("all")
        matplotlib.rc_file_defaults()
        sys.stdout.flush()
        sys.stderr.flush()


def run_recording(argv):
    """run(argv), and the paths its script (and its worker processes) wrote through _common, each
    once, in the order written."""
    global _record
    with tempfile.TemporaryFile() as record:
        _record = record.fileno()
        fcntl.fcntl(_record, fcntl.F_SETFL, fcntl.fcntl(_record, fcntl.F_GETFL) | os.O_APPEND)  # each path whole
        try:
            status = run(argv)
        finally:
            _record = None
        record.seek(0)  # every writer has ended: run() returns once the script's pool is closed
        wrote = list(dict.fromkeys(json.loads(line) for line in record.read().decode().splitlines()))
    return status, wrote


def main() -> int:
    with socket.socket(fileno=3) as channel, channel.makefile("r") as requests, channel.makefile("w") as answers:
        for line in requests:
            argv = json.loads(line)
            start = cpu_seconds()
            status, wrote = run_recording(argv)
            answers.write(json.dumps({"status": status, "cpu": round(cpu_seconds() - start, 3), "wrote": wrote}) + "\n")
            answers.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main())
