// The tile resolve's two sorted windows, held in registers (every index a literal constant: a
// dynamically indexed local array becomes per-lane scratch memory on a CPU device; docs/performance.md).
// Written by shaders/tile_windows.py, slot by slot for these sizes.
//
//   pending entries: pt[TILE_PENDING] (entry distance, the key), pe[] (its exit), ps[] (its sphere)
//   open exits:      xt[TILE_OPEN] (exit distance, the key), xs[] (its sphere)
//
// Empty slots hold NO_T, which sorts after every distance, so they gather at the end. Equal
// distances keep their arrival order: a zero-length segment lies between them, so the order
// changes nothing but rounding.
#ifndef BRUME_TILE_WINDOWS_GLSL
#define BRUME_TILE_WINDOWS_GLSL

const uint TILE_PENDING = 16u;
const uint TILE_OPEN = 32u;
const float NO_T = 3.4e38;

#define TILE_PENDING_CLEAR pt[0] = pt[1] = pt[2] = pt[3] = pt[4] = pt[5] = pt[6] = pt[7] = pt[8] = pt[9] = pt[10] = pt[11] = pt[12] = pt[13] = pt[14] = pt[15] = NO_T;
#define TILE_OPEN_CLEAR xt[0] = xt[1] = xt[2] = xt[3] = xt[4] = xt[5] = xt[6] = xt[7] = xt[8] = xt[9] = xt[10] = xt[11] = xt[12] = xt[13] = xt[14] = xt[15] = xt[16] = xt[17] = xt[18] = xt[19] = xt[20] = xt[21] = xt[22] = xt[23] = xt[24] = xt[25] = xt[26] = xt[27] = xt[28] = xt[29] = xt[30] = xt[31] = NO_T;

// Inserts an event in order (with c_i = (key < slot i): slot i takes its left neighbour if c_(i-1),
// else the key if c_i, else keeps its own); a key past the last slot falls off the end.
#define TILE_PENDING_INSERT(K_T, K_E, K_S) \
{ \
    float k_t = K_T; \
    float k_e = K_E; \
    uint k_s = K_S; \
    bool c0 = k_t < pt[0]; bool c1 = k_t < pt[1]; bool c2 = k_t < pt[2]; bool c3 = k_t < pt[3]; \
    bool c4 = k_t < pt[4]; bool c5 = k_t < pt[5]; bool c6 = k_t < pt[6]; bool c7 = k_t < pt[7]; \
    bool c8 = k_t < pt[8]; bool c9 = k_t < pt[9]; bool c10 = k_t < pt[10]; bool c11 = k_t < pt[11]; \
    bool c12 = k_t < pt[12]; bool c13 = k_t < pt[13]; bool c14 = k_t < pt[14]; bool c15 = k_t < pt[15]; \
    pt[15] = c14 ? pt[14] : (c15 ? k_t : pt[15]); pe[15] = c14 ? pe[14] : (c15 ? k_e : pe[15]); ps[15] = c14 ? ps[14] : (c15 ? k_s : ps[15]); \
    pt[14] = c13 ? pt[13] : (c14 ? k_t : pt[14]); pe[14] = c13 ? pe[13] : (c14 ? k_e : pe[14]); ps[14] = c13 ? ps[13] : (c14 ? k_s : ps[14]); \
    pt[13] = c12 ? pt[12] : (c13 ? k_t : pt[13]); pe[13] = c12 ? pe[12] : (c13 ? k_e : pe[13]); ps[13] = c12 ? ps[12] : (c13 ? k_s : ps[13]); \
    pt[12] = c11 ? pt[11] : (c12 ? k_t : pt[12]); pe[12] = c11 ? pe[11] : (c12 ? k_e : pe[12]); ps[12] = c11 ? ps[11] : (c12 ? k_s : ps[12]); \
    pt[11] = c10 ? pt[10] : (c11 ? k_t : pt[11]); pe[11] = c10 ? pe[10] : (c11 ? k_e : pe[11]); ps[11] = c10 ? ps[10] : (c11 ? k_s : ps[11]); \
    pt[10] = c9 ? pt[9] : (c10 ? k_t : pt[10]); pe[10] = c9 ? pe[9] : (c10 ? k_e : pe[10]); ps[10] = c9 ? ps[9] : (c10 ? k_s : ps[10]); \
    pt[9] = c8 ? pt[8] : (c9 ? k_t : pt[9]); pe[9] = c8 ? pe[8] : (c9 ? k_e : pe[9]); ps[9] = c8 ? ps[8] : (c9 ? k_s : ps[9]); \
    pt[8] = c7 ? pt[7] : (c8 ? k_t : pt[8]); pe[8] = c7 ? pe[7] : (c8 ? k_e : pe[8]); ps[8] = c7 ? ps[7] : (c8 ? k_s : ps[8]); \
    pt[7] = c6 ? pt[6] : (c7 ? k_t : pt[7]); pe[7] = c6 ? pe[6] : (c7 ? k_e : pe[7]); ps[7] = c6 ? ps[6] : (c7 ? k_s : ps[7]); \
    pt[6] = c5 ? pt[5] : (c6 ? k_t : pt[6]); pe[6] = c5 ? pe[5] : (c6 ? k_e : pe[6]); ps[6] = c5 ? ps[5] : (c6 ? k_s : ps[6]); \
    pt[5] = c4 ? pt[4] : (c5 ? k_t : pt[5]); pe[5] = c4 ? pe[4] : (c5 ? k_e : pe[5]); ps[5] = c4 ? ps[4] : (c5 ? k_s : ps[5]); \
    pt[4] = c3 ? pt[3] : (c4 ? k_t : pt[4]); pe[4] = c3 ? pe[3] : (c4 ? k_e : pe[4]); ps[4] = c3 ? ps[3] : (c4 ? k_s : ps[4]); \
    pt[3] = c2 ? pt[2] : (c3 ? k_t : pt[3]); pe[3] = c2 ? pe[2] : (c3 ? k_e : pe[3]); ps[3] = c2 ? ps[2] : (c3 ? k_s : ps[3]); \
    pt[2] = c1 ? pt[1] : (c2 ? k_t : pt[2]); pe[2] = c1 ? pe[1] : (c2 ? k_e : pe[2]); ps[2] = c1 ? ps[1] : (c2 ? k_s : ps[2]); \
    pt[1] = c0 ? pt[0] : (c1 ? k_t : pt[1]); pe[1] = c0 ? pe[0] : (c1 ? k_e : pe[1]); ps[1] = c0 ? ps[0] : (c1 ? k_s : ps[1]); \
    pt[0] = c0 ? k_t : pt[0]; pe[0] = c0 ? k_e : pe[0]; ps[0] = c0 ? k_s : ps[0]; \
}
#define TILE_OPEN_INSERT(K_T, K_S) \
{ \
    float k_t = K_T; \
    uint k_s = K_S; \
    bool c0 = k_t < xt[0]; bool c1 = k_t < xt[1]; bool c2 = k_t < xt[2]; bool c3 = k_t < xt[3]; \
    bool c4 = k_t < xt[4]; bool c5 = k_t < xt[5]; bool c6 = k_t < xt[6]; bool c7 = k_t < xt[7]; \
    bool c8 = k_t < xt[8]; bool c9 = k_t < xt[9]; bool c10 = k_t < xt[10]; bool c11 = k_t < xt[11]; \
    bool c12 = k_t < xt[12]; bool c13 = k_t < xt[13]; bool c14 = k_t < xt[14]; bool c15 = k_t < xt[15]; \
    bool c16 = k_t < xt[16]; bool c17 = k_t < xt[17]; bool c18 = k_t < xt[18]; bool c19 = k_t < xt[19]; \
    bool c20 = k_t < xt[20]; bool c21 = k_t < xt[21]; bool c22 = k_t < xt[22]; bool c23 = k_t < xt[23]; \
    bool c24 = k_t < xt[24]; bool c25 = k_t < xt[25]; bool c26 = k_t < xt[26]; bool c27 = k_t < xt[27]; \
    bool c28 = k_t < xt[28]; bool c29 = k_t < xt[29]; bool c30 = k_t < xt[30]; bool c31 = k_t < xt[31]; \
    xt[31] = c30 ? xt[30] : (c31 ? k_t : xt[31]); xs[31] = c30 ? xs[30] : (c31 ? k_s : xs[31]); \
    xt[30] = c29 ? xt[29] : (c30 ? k_t : xt[30]); xs[30] = c29 ? xs[29] : (c30 ? k_s : xs[30]); \
    xt[29] = c28 ? xt[28] : (c29 ? k_t : xt[29]); xs[29] = c28 ? xs[28] : (c29 ? k_s : xs[29]); \
    xt[28] = c27 ? xt[27] : (c28 ? k_t : xt[28]); xs[28] = c27 ? xs[27] : (c28 ? k_s : xs[28]); \
    xt[27] = c26 ? xt[26] : (c27 ? k_t : xt[27]); xs[27] = c26 ? xs[26] : (c27 ? k_s : xs[27]); \
    xt[26] = c25 ? xt[25] : (c26 ? k_t : xt[26]); xs[26] = c25 ? xs[25] : (c26 ? k_s : xs[26]); \
    xt[25] = c24 ? xt[24] : (c25 ? k_t : xt[25]); xs[25] = c24 ? xs[24] : (c25 ? k_s : xs[25]); \
    xt[24] = c23 ? xt[23] : (c24 ? k_t : xt[24]); xs[24] = c23 ? xs[23] : (c24 ? k_s : xs[24]); \
    xt[23] = c22 ? xt[22] : (c23 ? k_t : xt[23]); xs[23] = c22 ? xs[22] : (c23 ? k_s : xs[23]); \
    xt[22] = c21 ? xt[21] : (c22 ? k_t : xt[22]); xs[22] = c21 ? xs[21] : (c22 ? k_s : xs[22]); \
    xt[21] = c20 ? xt[20] : (c21 ? k_t : xt[21]); xs[21] = c20 ? xs[20] : (c21 ? k_s : xs[21]); \
    xt[20] = c19 ? xt[19] : (c20 ? k_t : xt[20]); xs[20] = c19 ? xs[19] : (c20 ? k_s : xs[20]); \
    xt[19] = c18 ? xt[18] : (c19 ? k_t : xt[19]); xs[19] = c18 ? xs[18] : (c19 ? k_s : xs[19]); \
    xt[18] = c17 ? xt[17] : (c18 ? k_t : xt[18]); xs[18] = c17 ? xs[17] : (c18 ? k_s : xs[18]); \
    xt[17] = c16 ? xt[16] : (c17 ? k_t : xt[17]); xs[17] = c16 ? xs[16] : (c17 ? k_s : xs[17]); \
    xt[16] = c15 ? xt[15] : (c16 ? k_t : xt[16]); xs[16] = c15 ? xs[15] : (c16 ? k_s : xs[16]); \
    xt[15] = c14 ? xt[14] : (c15 ? k_t : xt[15]); xs[15] = c14 ? xs[14] : (c15 ? k_s : xs[15]); \
    xt[14] = c13 ? xt[13] : (c14 ? k_t : xt[14]); xs[14] = c13 ? xs[13] : (c14 ? k_s : xs[14]); \
    xt[13] = c12 ? xt[12] : (c13 ? k_t : xt[13]); xs[13] = c12 ? xs[12] : (c13 ? k_s : xs[13]); \
    xt[12] = c11 ? xt[11] : (c12 ? k_t : xt[12]); xs[12] = c11 ? xs[11] : (c12 ? k_s : xs[12]); \
    xt[11] = c10 ? xt[10] : (c11 ? k_t : xt[11]); xs[11] = c10 ? xs[10] : (c11 ? k_s : xs[11]); \
    xt[10] = c9 ? xt[9] : (c10 ? k_t : xt[10]); xs[10] = c9 ? xs[9] : (c10 ? k_s : xs[10]); \
    xt[9] = c8 ? xt[8] : (c9 ? k_t : xt[9]); xs[9] = c8 ? xs[8] : (c9 ? k_s : xs[9]); \
    xt[8] = c7 ? xt[7] : (c8 ? k_t : xt[8]); xs[8] = c7 ? xs[7] : (c8 ? k_s : xs[8]); \
    xt[7] = c6 ? xt[6] : (c7 ? k_t : xt[7]); xs[7] = c6 ? xs[6] : (c7 ? k_s : xs[7]); \
    xt[6] = c5 ? xt[5] : (c6 ? k_t : xt[6]); xs[6] = c5 ? xs[5] : (c6 ? k_s : xs[6]); \
    xt[5] = c4 ? xt[4] : (c5 ? k_t : xt[5]); xs[5] = c4 ? xs[4] : (c5 ? k_s : xs[5]); \
    xt[4] = c3 ? xt[3] : (c4 ? k_t : xt[4]); xs[4] = c3 ? xs[3] : (c4 ? k_s : xs[4]); \
    xt[3] = c2 ? xt[2] : (c3 ? k_t : xt[3]); xs[3] = c2 ? xs[2] : (c3 ? k_s : xs[3]); \
    xt[2] = c1 ? xt[1] : (c2 ? k_t : xt[2]); xs[2] = c1 ? xs[1] : (c2 ? k_s : xs[2]); \
    xt[1] = c0 ? xt[0] : (c1 ? k_t : xt[1]); xs[1] = c0 ? xs[0] : (c1 ? k_s : xs[1]); \
    xt[0] = c0 ? k_t : xt[0]; xs[0] = c0 ? k_s : xs[0]; \
}

// Drops slot 0 and moves every slot one place left.
#define TILE_PENDING_SHIFT_LEFT \
{ \
    pt[0] = pt[1]; pt[1] = pt[2]; pt[2] = pt[3]; pt[3] = pt[4]; pt[4] = pt[5]; pt[5] = pt[6]; pt[6] = pt[7]; pt[7] = pt[8]; pt[8] = pt[9]; pt[9] = pt[10]; pt[10] = pt[11]; pt[11] = pt[12]; pt[12] = pt[13]; pt[13] = pt[14]; pt[14] = pt[15]; \
    pe[0] = pe[1]; pe[1] = pe[2]; pe[2] = pe[3]; pe[3] = pe[4]; pe[4] = pe[5]; pe[5] = pe[6]; pe[6] = pe[7]; pe[7] = pe[8]; pe[8] = pe[9]; pe[9] = pe[10]; pe[10] = pe[11]; pe[11] = pe[12]; pe[12] = pe[13]; pe[13] = pe[14]; pe[14] = pe[15]; \
    ps[0] = ps[1]; ps[1] = ps[2]; ps[2] = ps[3]; ps[3] = ps[4]; ps[4] = ps[5]; ps[5] = ps[6]; ps[6] = ps[7]; ps[7] = ps[8]; ps[8] = ps[9]; ps[9] = ps[10]; ps[10] = ps[11]; ps[11] = ps[12]; ps[12] = ps[13]; ps[13] = ps[14]; ps[14] = ps[15]; \
    pt[15] = NO_T; \
}
#define TILE_OPEN_SHIFT_LEFT \
{ \
    xt[0] = xt[1]; xt[1] = xt[2]; xt[2] = xt[3]; xt[3] = xt[4]; xt[4] = xt[5]; xt[5] = xt[6]; xt[6] = xt[7]; xt[7] = xt[8]; xt[8] = xt[9]; xt[9] = xt[10]; xt[10] = xt[11]; xt[11] = xt[12]; xt[12] = xt[13]; xt[13] = xt[14]; xt[14] = xt[15]; xt[15] = xt[16]; xt[16] = xt[17]; xt[17] = xt[18]; xt[18] = xt[19]; xt[19] = xt[20]; xt[20] = xt[21]; xt[21] = xt[22]; xt[22] = xt[23]; xt[23] = xt[24]; xt[24] = xt[25]; xt[25] = xt[26]; xt[26] = xt[27]; xt[27] = xt[28]; xt[28] = xt[29]; xt[29] = xt[30]; xt[30] = xt[31]; \
    xs[0] = xs[1]; xs[1] = xs[2]; xs[2] = xs[3]; xs[3] = xs[4]; xs[4] = xs[5]; xs[5] = xs[6]; xs[6] = xs[7]; xs[7] = xs[8]; xs[8] = xs[9]; xs[9] = xs[10]; xs[10] = xs[11]; xs[11] = xs[12]; xs[12] = xs[13]; xs[13] = xs[14]; xs[14] = xs[15]; xs[15] = xs[16]; xs[16] = xs[17]; xs[17] = xs[18]; xs[18] = xs[19]; xs[19] = xs[20]; xs[20] = xs[21]; xs[21] = xs[22]; xs[22] = xs[23]; xs[23] = xs[24]; xs[24] = xs[25]; xs[25] = xs[26]; xs[26] = xs[27]; xs[27] = xs[28]; xs[28] = xs[29]; xs[29] = xs[30]; xs[30] = xs[31]; \
    xt[31] = NO_T; \
}

#endif
