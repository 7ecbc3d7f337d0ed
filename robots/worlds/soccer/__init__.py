"""The named soccer fields (:mod:`robots.soccer.fieldfile`), shipped as JSON package data apart from the named
worlds, which are navigation worlds; ``ekm match --field NAME`` plays on one."""
