"""The ``axojax`` command line (see docs/interface.md). One module per subcommand."""
