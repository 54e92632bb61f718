"""The one way in: the registry of mechanism families (``registry``: which family a description
belongs to, ``load``) and each family's implementation of the stage interface (``family``)."""
