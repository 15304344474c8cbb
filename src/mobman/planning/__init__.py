"""Endogenous-configuration motion planning (Tchoń, Jakubiak & Muszyński 2002)."""
