"""The named worlds (docs/design.md §2), shipped as JSON package data; list them with ``ekm worlds``."""
