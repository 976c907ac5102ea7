"""Joint sets from field data: a scanline survey read, each set's orientation, spacing and trace
length fitted with the corrections a scanline needs, and the sets written as a scene's joint sets
(`bbmc joints`, docs/field-data.md)."""
