"""Helper threads that share a compiled kernel's chunks of rows with the calling thread.

``threads.py`` starts and parks the helpers and hands them a kernel run
(:class:`Flight`); ``chunks.py`` is the compiled side: how a kernel takes its
chunks in turn, and how the caller and the helpers meet at its end. The ray
kernel (``mimics.engine.ranging``), the collision checks
(``mimics.engine.motion_checks``) and the ranger's noise (``mimics.engine.ranging.ranger_noise``)
run on them.
"""
