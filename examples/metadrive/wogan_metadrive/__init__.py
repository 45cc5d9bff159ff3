"""wogan's MetaDrive executor, as a package: its entry script is examples/metadrive/executor.py."""
