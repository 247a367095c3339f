"""Package data: published reference figures (see README.md in this folder)."""
