"""How a command ends: the expected failures as one line on stderr and an exit status, and the files
it wrote, one line each (`bbmc.cli`'s commands run their work inside `reported`)."""

from __future__ import annotations

import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import click

from bbmc.config import ConfigError, ConfigKeyError
from bbmc.dem.solver import SimulationError
from bbmc.exit_status import BAD_INPUT, INTERRUPTED, NO_SAMPLE, UNSTABLE, WRITE_FAILED
from bbmc.plausibility import ImplausibleValue
from bbmc.sweep.study import NoValidSampleError


@contextmanager
def reported(name: str, strict: bool = False) -> Iterator[None]:
    """Turn the expected failures into one line on stderr and an exit status: 2 for bad input (the
    config, an input file, an unusable time step), 3 for a run that went unstable, 4 for a study in
    which no sample gave a result (its first errors, a few lines), 1 for a failed write, 130 for Ctrl-C
    (what a sweep keeps, if it says so; nothing else is written). An implausible value of a config
    loaded meanwhile is one warning line (each once), or with `strict` bad input. Python's other
    warnings on the way (numpy's overflow, say, from an input far out of range) are shown one line
    each after a run that ends well, and dropped beside the error line of one that does not (it says
    what went wrong)."""
    shown: set[str] = set()
    deferred: dict[str, None] = {}  # the other warnings, each once, for after a run that ends well

    def show(message: Warning | str, category: type[Warning], *where: object, **more: object) -> None:
        if not issubclass(category, ImplausibleValue):
            deferred[f"{category.__name__}: {message}"] = None
        elif str(message) not in shown:
            shown.add(str(message))
            click.echo(f"bbmc {name}: warning: {message}", err=True)

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("default")
            warnings.simplefilter("error" if strict else "always", ImplausibleValue)
            warnings.showwarning = show
            yield
    except (KeyboardInterrupt, SystemError) as error:
        interrupt = interrupt_behind(error)
        if interrupt is None:
            raise
        kept = f"{interrupt}; nothing else written" if str(interrupt) else "nothing written"
        click.echo(f"bbmc {name}: interrupted: {kept}", err=True)
        sys.exit(INTERRUPTED)
    except ImplausibleValue as error:
        click.echo(f"bbmc {name}: error: {error} [--strict]", err=True)
        sys.exit(BAD_INPUT)
    except ConfigError as error:
        click.echo(f"bbmc {name}: error: {error}", err=True)
        sys.exit(BAD_INPUT)
    except NoValidSampleError as error:
        click.echo(f"bbmc {name}: error: {error}", err=True)
        sys.exit(NO_SAMPLE)
    except SimulationError as error:
        click.echo(f"bbmc {name}: error: {error}", err=True)
        sys.exit(BAD_INPUT if error.bad_input else UNSTABLE)
    except OSError as error:
        click.echo(f"bbmc {name}: error: cannot write results: {error}", err=True)
        sys.exit(WRITE_FAILED)
    for text in deferred:
        click.echo(f"bbmc {name}: warning: {text}", err=True)


def interrupt_behind(error: BaseException | None) -> KeyboardInterrupt | None:
    """The Ctrl-C behind an error, if any: numba turns a KeyboardInterrupt raised in Python code that a
    kernel calls back (to unpickle a constant) into a SystemError caused by it."""
    while error is not None:
        if isinstance(error, KeyboardInterrupt):
            return error
        error = error.__cause__ or error.__context__
    return None


@contextmanager
def scene_at_fault(config_path: Path) -> Iterator[None]:
    """A run stopped by its scene or config itself (an unusable time step, a step budget too small to
    decide, a key the run found meaningless) is bad input naming the file."""
    try:
        yield
    except ConfigKeyError as error:
        raise ConfigError(f"{config_path}: {error}") from None
    except SimulationError as error:
        if error.bad_input:
            raise ConfigError(f"{config_path}: {error}") from None
        raise


def report_written(name: str, out_dir: Path, written: list[Path]) -> None:
    """One line per file written into `out_dir` itself, and one per folder in it (a ParaView series of
    hundreds of files is one line: the folder and its file count)."""
    click.echo(f"bbmc {name}: wrote {len(written)} files to {out_dir}/")
    folders: dict[Path, int] = {}
    for path in written:
        inner = path.relative_to(out_dir).parts
        if len(inner) == 1:
            click.echo(f"  {path}")
        else:
            folders[out_dir / inner[0]] = folders.get(out_dir / inner[0], 0) + 1
    for folder, count in folders.items():
        click.echo(f"  {folder}/ ({count} files)")
