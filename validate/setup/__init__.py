"""What the suite needs besides Python, where it lives and how it is installed.

:mod:`.paths` says where (a per-user data folder, the same for a checkout and an installed wheel);
:mod:`.install` is ``python -m validate setup [--engines|--system] [--check]``.
"""
