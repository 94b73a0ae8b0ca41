# machine: os
# Bundle syntax errors: ';' outside braces, an unknown slot, an unterminated bundle.
        add r1, r2, r3 ; add r4, r5, r6
        { xu0: add r1, r2, r3 }
        { add r1, r2, r3
        halt
