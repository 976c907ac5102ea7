"""Stages: each reads one validated config and returns tables and figures (`bbmc.io.StageResult`).

A stage module defines `NAME`, a pydantic `Config` and `run(config) -> StageResult`; the command line
loads the config, runs the stage and writes the result atomically into `results/<NAME>/`.
"""
