// placeholder: the `ricci render` subcommand and `param --pictures`, filled in by its owner.
