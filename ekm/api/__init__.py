"""The Python API behind ``import ekm`` (:mod:`ekm` re-exports it lazily) and behind the command line.

One module per command, each holding its function and its result: :mod:`~ekm.api.training` (``train``,
``resume``), :mod:`~ekm.api.mapset` (``load``, ``Maps``, ``Map``), :mod:`~ekm.api.evaluation`
(``evaluate``, ``Metrics``), :mod:`~ekm.api.worlds` (``world``, ``worlds``), :mod:`~ekm.api.planning`
(``plan``, ``Plan``), :mod:`~ekm.api.driving` (``run``, ``Outcome``), :mod:`~ekm.api.comparing`
(``compare``, ``load_comparison``, ``Table``), :mod:`~ekm.api.robots` (``robot``, ``robots``),
:mod:`~ekm.api.adapting` (``adapt``, ``AdaptationTable``), :mod:`~ekm.api.catalogue` (what a user can add:
``architectures``, ``players``, ``families`` and their ``register_*``), :mod:`~ekm.api.soccer` (``match``,
``tournament``, ``soccer_field``, ``MatchResult``, ``TournamentResult``); :mod:`~ekm.api.checks` checks arguments
with the command line's messages and :mod:`~ekm.api.result` holds what the results share (``to_dict``). Nothing here imports JAX or pymunk
until a function runs.
"""
