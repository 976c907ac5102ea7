"""The `bbmc` program (its console script and `python -m bbmc`): the command line of `bbmc.cli`, with
Ctrl-C answered by one line and exit status 130 from its first instant to its last.

`bbmc.cli` answers a Ctrl-C during a command. Here, the rest: during the imports (about 2 s: numpy,
numba, pandas, matplotlib), and once a command has ended, when a second Ctrl-C would otherwise print a
traceback from the interpreter's shutdown (about 0.4 s): it is ignored then.
"""

from __future__ import annotations

import signal
import sys

from bbmc.exit_status import INTERRUPTED


def run() -> None:
    try:
        from bbmc.cli import main  # here: a Ctrl-C during the imports is answered too
    except KeyboardInterrupt:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        sys.stderr.write("bbmc: interrupted: nothing written\n")
        sys.exit(INTERRUPTED)
    try:
        main()
    finally:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
