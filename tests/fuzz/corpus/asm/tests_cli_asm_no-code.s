# machine: os
# No code at all: the object would have nothing to run, which deserves a warning.
