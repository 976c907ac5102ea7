from bbmc.cli import main

main()
