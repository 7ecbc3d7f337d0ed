"""The named robots (docs/design.md §2, §10), shipped as robot files; list them with ``ekm robots``."""
