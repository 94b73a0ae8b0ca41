# machine: os
# More than 20 errors: the first 20 are reported, then the assembler stops (clang's -ferror-limit).
        bogus0 r1, r2
        bogus1 r1, r2
        bogus2 r1, r2
        bogus3 r1, r2
        bogus4 r1, r2
        bogus5 r1, r2
        bogus6 r1, r2
        bogus7 r1, r2
        bogus8 r1, r2
        bogus9 r1, r2
        bogus10 r1, r2
        bogus11 r1, r2
        bogus12 r1, r2
        bogus13 r1, r2
        bogus14 r1, r2
        bogus15 r1, r2
        bogus16 r1, r2
        bogus17 r1, r2
        bogus18 r1, r2
        bogus19 r1, r2
        bogus20 r1, r2
        bogus21 r1, r2
        bogus22 r1, r2
        bogus23 r1, r2
        bogus24 r1, r2
        halt
