"""The engines that run a Lepp refinement: ``reference`` (the pure steps on a transient),
``batch`` (Python, plain dicts) and ``compiled`` (the Cython kernel).  All three record
the same trace."""
