"""What a run and a factor of safety leave for the reader: their figures (`figures`) and ParaView files
(`vtk`), drawn from the engine's and the analyses' results."""
