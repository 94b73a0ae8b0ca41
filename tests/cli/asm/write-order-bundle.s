# machine: os
# One bundle writes f1 twice with different latencies. The ISS issues a bundle's operations in
# slot order: the fdiv (fpu0) is the earlier write, and the fadd (fpu1) would land before it.
        { fdiv f1, f2, f3 ; fadd f1, f4, f5 }
        halt
