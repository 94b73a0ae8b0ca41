# machine: os
# One bundle receives two words from channel 0. Fed a single word on a closed channel it can
# never issue: a deadlock for sim, lock-step and the debugger alike (not a wait to the cycle limit).
        { recv r1, 0 ; recv r2, 0 }
        halt
