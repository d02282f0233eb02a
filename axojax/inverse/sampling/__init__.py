"""Posteriors of an inverse problem (:class:`axojax.inverse.Problem`): NUTS chains
(:mod:`.posterior`), adaptive tempered SMC runs for several modes and cliffs (:mod:`.smc`,
settings and compiled run in :mod:`._smc`), the coordinates that straighten a curved ridge for them
(:mod:`.transport`, :mod:`.transport_choice`), their start-up cache and diagnostics.
Imports the fit layer (:mod:`axojax.inverse`'s modules), never the package itself."""
