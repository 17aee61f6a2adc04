"""Kinematics and coordinate transformations (seed 002 ch. 17; spec 05 §6, spec 07 §B.8).

* :mod:`fagorcnc.config.kinematics`: ``[[kinematics]]`` and ``[[angular_axes]]`` of the machine file;
* :mod:`.rotation`, :mod:`.solve`: forward and inverse kinematics;
* :mod:`.frames`: the #CS/#ACS definition modes and their composition;
* :mod:`.frame`: the transformation of a record (``record.frame``) from the interpreter's coordinates
  to machine joints;
* :mod:`.state`, :mod:`.statements`: #KIN ID, #CS, #ACS, #RTCP, #TLC, #TOOL ORI;
* :mod:`.stage`: the joint-space stage after radius compensation;
* :mod:`.caxis` (#FACE, #CYL), :mod:`.angax` (#ANGAX), :mod:`.tangential` (G45, G145, #TANGCTRL);
* :mod:`.variables` (V.MPK, V.G.TOOLORI*...), :mod:`.tip` (the tool tip of a sampled trajectory).
"""
