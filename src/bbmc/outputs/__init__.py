"""What a run and a factor of safety leave for the reader: their figures (`figures`) and ParaView files
(`vtk`), drawn from the engine's and the analyses' results; a wedge's figures (`wedge_figures`), VTK
file (`wedge_vtk`), the tables of the figures' numbers (`wedge_figure_tables`) and those of `bbmc
wedge` (`wedge_tables`)."""
