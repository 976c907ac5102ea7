"""The scene format, an input: every key of a scene file as pydantic models (`schema`) and its `fos:`
section (`fos_settings`). The engine (`bbmc.dem`) builds its arrays from a validated scene; nothing here
imports the engine."""
