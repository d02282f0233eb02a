"""The ``axojax`` command line (see INTERFACE.md). One module per subcommand."""
