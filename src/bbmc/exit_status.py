"""The exit statuses of the `bbmc` program: what each way a command ends tells the shell.

The lowest layer: the program's entry (`bbmc.program`) needs `INTERRUPTED` before it imports anything
else, and `bbmc.command_outcome` all of them.
"""

WRITE_FAILED = 1  # a result could not be written
BAD_INPUT = 2  # the config, an input file or the scene is at fault
UNSTABLE = 3  # a run went unstable
NO_SAMPLE = 4  # a study in which no sample gave a result
INTERRUPTED = 130  # 128 + SIGINT: the shell's status for a program stopped by Ctrl-C
