"""Slippery-cell planning in the workspace (thesis ch. 3): bitmap, labelling, graph, search, checkpoints."""
