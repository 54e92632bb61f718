"""The MuJoCo side of every family: MJCF writers (a planar linkage's spanning tree plus
loop-closing ``connect``s, a cam's contact pair, a spatial four-bar's chain, a machine's motor),
settings derived from the mechanism, the runs and the read-out of joint forces. Modules named
after a family are that family's; the others are the planar linkage's or shared."""
