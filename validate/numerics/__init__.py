"""Numerical tools below every user: drjit-AD fits (:mod:`.adfit`: scipy's least-squares and minimise with
reverse-mode gradients) and the thread-local BLAS switch (:mod:`.blas`)."""
