"""What `bbmc bench` measures on the paper's scenes: the speed-accuracy trade of the solver's knobs,
the gain of each piece of work the engine leaves out, and the engine's growth with the block count."""
