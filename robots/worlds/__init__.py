"""The named worlds (DESIGN §2), shipped as JSON package data; list them with ``ekm worlds``."""
