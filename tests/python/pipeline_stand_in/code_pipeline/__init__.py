"""Stand-in for the tool competition pipeline's code_pipeline package (tests only)."""
