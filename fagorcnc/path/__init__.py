"""Path geometry: arcs in every form (more to come: compensation, corner aids, transformations)."""
