"""The seeds' lighting listings and printed equations as techniques (see ``docs/listings.md``)."""
