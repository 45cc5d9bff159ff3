"""Stand-in for the tool competition pipeline's self_driving package (tests only)."""
