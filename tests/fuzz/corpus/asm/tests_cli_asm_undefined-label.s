# machine: os
# A branch to a label that does not exist.
        beqz r1, nowhere
        halt
