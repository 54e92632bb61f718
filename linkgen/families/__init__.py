"""The closed form of every mechanism family, one subpackage each: ``planar`` (linkages by Assur
groups, with cams and gears as higher pairs), ``cam`` (stand-alone disc cams), ``spatial``
(spatial four-bars). Each turns its validated description (``linkgen.model``) into named
quantities over arrays of crank angles; nothing here writes MJCF or runs MuJoCo."""
