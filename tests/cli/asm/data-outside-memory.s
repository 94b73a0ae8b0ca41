# machine: ic
# Data no memory region holds whole is an error here, not only when the object is loaded: a
# section outside every region, and one that runs over the end of resident memory.
        halt
        .data 0x7ff00000
far:    .word 1, 2
        .data 0x004ffffc
over:   .word 3, 4
        .data 0x00400000
ok:     .word 5
