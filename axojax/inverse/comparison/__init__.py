"""Which dynein mechanism a beat supports: the hypotheses (mechanism x base,
:mod:`.mechanisms`) fitted to one beat and ranked (:mod:`.compare`). Imports the fit
layer (:mod:`axojax.inverse`'s modules) and the Laplace approximation of
:mod:`axojax.inverse.sampling`, never the package itself."""
