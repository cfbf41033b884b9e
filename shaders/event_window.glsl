// Sorted windows of event keys held in registers, for the exact resolves. Every index is a literal
// constant, so on a CPU device a window stays in SIMD registers (a dynamically indexed local array
// becomes per-lane scratch loads and stores; docs/performance.md). The macros work on local arrays
// the caller declares: `uvec2 w[WINDOW]` (the general path) and `uvec2 q[ORDERED_WINDOW]` (the
// ordered path). They are written out slot by slot for these sizes.
//
// A key is (floatBitsToUint(distance), sphere * 2 + is_exit): unique per pixel, and, since
// distances are >= +0.0, ordered like the floats. NO_KEY marks an empty slot; it sorts after every
// real key, so empty slots gather at the end.
#ifndef BRUME_EVENT_WINDOW_GLSL
#define BRUME_EVENT_WINDOW_GLSL

const uint WINDOW = 8;
const uint ORDERED_WINDOW = 32;
const uvec2 NO_KEY = uvec2(0xffffffffu);

bool key_less(uvec2 a, uvec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); }

// The general path's window: whole keys, so that "the keys after the last one taken" is exact
// even among equal distances. Small, because every pixel runs its code once (a list of up to 4
// nodes needs nothing else), and lavapipe runs code under empty lane masks too.
#define BRUME_WINDOW_CLEAR w[0] = w[1] = w[2] = w[3] = w[4] = w[5] = w[6] = w[7] = NO_KEY;

// Inserts k in order; when the window is full, the largest key falls off the end. With
// c_i = (k sorts before slot i), slot i takes its left neighbour if c_(i-1), else k if c_i, else
// keeps its own. All comparisons use the window as it was, so they are made before any slot moves.
#define BRUME_WINDOW_INSERT(k)                                                                              \
    {                                                                                                       \
        uvec2 key = k;                                                                                      \
        bool c0 = key_less(key, w[0]); bool c1 = key_less(key, w[1]); bool c2 = key_less(key, w[2]);        \
        bool c3 = key_less(key, w[3]); bool c4 = key_less(key, w[4]); bool c5 = key_less(key, w[5]);        \
        bool c6 = key_less(key, w[6]); bool c7 = key_less(key, w[7]);                                       \
        w[7] = c6 ? w[6] : (c7 ? key : w[7]); w[6] = c5 ? w[5] : (c6 ? key : w[6]);                         \
        w[5] = c4 ? w[4] : (c5 ? key : w[5]); w[4] = c3 ? w[3] : (c4 ? key : w[4]);                         \
        w[3] = c2 ? w[2] : (c3 ? key : w[3]); w[2] = c1 ? w[1] : (c2 ? key : w[2]);                         \
        w[1] = c0 ? w[0] : (c1 ? key : w[1]); w[0] = c0 ? key : w[0];                                       \
    }

// Drops slot 0 and moves every slot one place left.
#define BRUME_WINDOW_SHIFT_LEFT                                                                             \
    {                                                                                                       \
        w[0] = w[1]; w[1] = w[2]; w[2] = w[3]; w[3] = w[4]; w[4] = w[5]; w[5] = w[6]; w[6] = w[7];          \
        w[7] = NO_KEY;                                                                                      \
    }

// The ordered path's window compares distances only: equal distances keep their arrival order,
// which changes nothing but rounding (a zero-length segment lies between them), and one compare
// per slot instead of three is most of the cost of an insertion.
#define BRUME_ORDERED_CLEAR q[0] = q[1] = q[2] = q[3] = q[4] = q[5] = q[6] = q[7] = q[8] = q[9] = q[10] = q[11] = q[12] = q[13] = q[14] = q[15] = q[16] = q[17] = q[18] = q[19] = q[20] = q[21] = q[22] = q[23] = q[24] = q[25] = q[26] = q[27] = q[28] = q[29] = q[30] = q[31] = NO_KEY;

#define BRUME_ORDERED_INSERT(k)                                                                             \
    {                                                                                                       \
        uvec2 key = k;                                                                                      \
        bool c0 = key.x < q[0].x; bool c1 = key.x < q[1].x; bool c2 = key.x < q[2].x;                       \
        bool c3 = key.x < q[3].x; bool c4 = key.x < q[4].x; bool c5 = key.x < q[5].x;                       \
        bool c6 = key.x < q[6].x; bool c7 = key.x < q[7].x; bool c8 = key.x < q[8].x;                       \
        bool c9 = key.x < q[9].x; bool c10 = key.x < q[10].x; bool c11 = key.x < q[11].x;                   \
        bool c12 = key.x < q[12].x; bool c13 = key.x < q[13].x; bool c14 = key.x < q[14].x;                 \
        bool c15 = key.x < q[15].x; bool c16 = key.x < q[16].x; bool c17 = key.x < q[17].x;                 \
        bool c18 = key.x < q[18].x; bool c19 = key.x < q[19].x; bool c20 = key.x < q[20].x;                 \
        bool c21 = key.x < q[21].x; bool c22 = key.x < q[22].x; bool c23 = key.x < q[23].x;                 \
        bool c24 = key.x < q[24].x; bool c25 = key.x < q[25].x; bool c26 = key.x < q[26].x;                 \
        bool c27 = key.x < q[27].x; bool c28 = key.x < q[28].x; bool c29 = key.x < q[29].x;                 \
        bool c30 = key.x < q[30].x; bool c31 = key.x < q[31].x;                                             \
        q[31] = c30 ? q[30] : (c31 ? key : q[31]); q[30] = c29 ? q[29] : (c30 ? key : q[30]);               \
        q[29] = c28 ? q[28] : (c29 ? key : q[29]); q[28] = c27 ? q[27] : (c28 ? key : q[28]);               \
        q[27] = c26 ? q[26] : (c27 ? key : q[27]); q[26] = c25 ? q[25] : (c26 ? key : q[26]);               \
        q[25] = c24 ? q[24] : (c25 ? key : q[25]); q[24] = c23 ? q[23] : (c24 ? key : q[24]);               \
        q[23] = c22 ? q[22] : (c23 ? key : q[23]); q[22] = c21 ? q[21] : (c22 ? key : q[22]);               \
        q[21] = c20 ? q[20] : (c21 ? key : q[21]); q[20] = c19 ? q[19] : (c20 ? key : q[20]);               \
        q[19] = c18 ? q[18] : (c19 ? key : q[19]); q[18] = c17 ? q[17] : (c18 ? key : q[18]);               \
        q[17] = c16 ? q[16] : (c17 ? key : q[17]); q[16] = c15 ? q[15] : (c16 ? key : q[16]);               \
        q[15] = c14 ? q[14] : (c15 ? key : q[15]); q[14] = c13 ? q[13] : (c14 ? key : q[14]);               \
        q[13] = c12 ? q[12] : (c13 ? key : q[13]); q[12] = c11 ? q[11] : (c12 ? key : q[12]);               \
        q[11] = c10 ? q[10] : (c11 ? key : q[11]); q[10] = c9 ? q[9] : (c10 ? key : q[10]);                 \
        q[9] = c8 ? q[8] : (c9 ? key : q[9]); q[8] = c7 ? q[7] : (c8 ? key : q[8]);                         \
        q[7] = c6 ? q[6] : (c7 ? key : q[7]); q[6] = c5 ? q[5] : (c6 ? key : q[6]);                         \
        q[5] = c4 ? q[4] : (c5 ? key : q[5]); q[4] = c3 ? q[3] : (c4 ? key : q[4]);                         \
        q[3] = c2 ? q[2] : (c3 ? key : q[3]); q[2] = c1 ? q[1] : (c2 ? key : q[2]);                         \
        q[1] = c0 ? q[0] : (c1 ? key : q[1]); q[0] = c0 ? key : q[0];                                       \
    }

#define BRUME_ORDERED_SHIFT_LEFT                                                                            \
    {                                                                                                       \
        q[0] = q[1]; q[1] = q[2]; q[2] = q[3]; q[3] = q[4]; q[4] = q[5]; q[5] = q[6]; q[6] = q[7];          \
        q[7] = q[8]; q[8] = q[9]; q[9] = q[10]; q[10] = q[11]; q[11] = q[12]; q[12] = q[13];                \
        q[13] = q[14]; q[14] = q[15]; q[15] = q[16]; q[16] = q[17]; q[17] = q[18]; q[18] = q[19];           \
        q[19] = q[20]; q[20] = q[21]; q[21] = q[22]; q[22] = q[23]; q[23] = q[24]; q[24] = q[25];           \
        q[25] = q[26]; q[26] = q[27]; q[27] = q[28]; q[28] = q[29]; q[29] = q[30]; q[30] = q[31];           \
        q[31] = NO_KEY;                                                                                     \
    }

#endif
