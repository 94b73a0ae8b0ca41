# machine: os
        beqz r1, done
done:   halt
