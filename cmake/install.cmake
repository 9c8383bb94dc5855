# Installation rules: filled in by their owner.
