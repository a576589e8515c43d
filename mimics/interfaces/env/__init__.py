"""Learning environments: the robots of a scenario as PettingZoo and Gymnasium agents.

One module per concern: :mod:`.observations` (what an agent sees, as a
``Dict`` or a flat ``Box``), :mod:`.actions` (speed and heading references,
fed to the engine as an algorithm), :mod:`.rewards` (the default reward and
what a user's reward or termination function receives), :mod:`.parallel`
(the ``ParallelEnv``) and :mod:`.single` (one robot as a Gymnasium ``Env``).
Importing this package imports PettingZoo and Gymnasium (the ``rl`` extra);
``import mimics`` does not.
"""
