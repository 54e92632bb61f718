"""Design studies: sweeps of a description's numeric fields and optimisation over them.

``fields`` reads ``--vary`` specifications and applies their values to the parsed TOML;
``samples`` draws the grid or the Latin hypercube; ``metrics`` names the design metrics every
route gives, with units; ``general`` computes them for one variant through the planar closed
form (``families.planar``), ``fourbar`` for many four-bar variants at once (one array per
quantity, variants × crank angles); ``engine`` splits a study into chunks, runs them on local
processes or a Dask cluster and writes each chunk as it finishes (a killed sweep resumes from
them); ``table`` writes the Parquet and CSV tables with their provenance; ``plots`` draws the
maps; ``validate`` runs a sample in MuJoCo; ``optimize`` searches the varied fields."""
