from bbmc.program import run

run()
