// Product sampling of environment x BRDF over env-hier's unit square, for the `product` strategies
// (engine/sampling/product/env_hier_product.h documents the method and holds the CPU twin,
// EnvProductSampler). Needs the env technique env-hier, whose builder also provides the nodes' tables and
// PRODUCT_* defines. The nodes are a pyramid level (default) or, with PRODUCT_UNIFORM_GRID defined by the
// strategy part before including this file, a uniform grid over u (warp composition, `product-warp`). With
// PRODUCT_TAIL_ENV_OT (defined by envOtProductTechniqueData, engine/sampling/product/env_ot_product.h) the
// grid is over env-ot's unit square instead
// (`product-warp-ot`), whose warp reaches a split sun's texels twice: the pdf sums over both preimages.
//
// productPrepare(s), once per shading point: weights w_j = (1 - d) E_j F_j / sum_k E_k F_k + d E_j over the
// level's nodes (E_j the node's env-hier probability, F_j = mean_rgb(f) cos at the node's direction closest
// to the mirror direction of wo, d = PRODUCT_DEFENSIVE), kept as 16-bit running sums per row
// (gProductColumnSums) and over rows (gProductRowSums; kProductFullScale gives the rule). With
// PRODUCT_TABLE_BINDING (the host's choice when the image's tables fit PRODUCT_TABLE_CHUNKS buffers:
// engine/render/renderer.cpp) the kernel built with PRODUCT_TABLE_BUILD, dispatched first after a restart,
// stores each pixel's sums in its chunk, two per word, and every dispatch of the accumulation samples from the
// stored sums instead of evaluating the BRDF at every node again (once per accumulation, not once per dispatch
// of at most 256 samples). The integrator holds no code that builds tables: lavapipe (Mesa 22) runs the body
// of every branch, taken or not, under a lane mask, so a build behind `frame.sampleOffset == 0` cost every
// dispatch (docs/BENCHMARKS.md, "Product strategies"). A dispatch of many samples copies the sums into
// private memory and scans them, one of few samples reads the rows' sums and then binary-searches the chosen
// row's words in the buffer. productSample chooses a row by u.y and a node in it by u.x, rescales u inside
// the choice, fills the node's rectangle in u with it and lets env-hier's descent (envSample) finish, so
// pdf = P(j) / E_j * p_env-hier, with P(j) computed from the same sums in sampling and in productPdf.
//
// On a pyramid level with PRODUCT_REFINE_DEPTH > 0, the table also splits the nodes of largest E_j F_j into
// their children on the next level, and the largest of those children once more (the refinement:
// engine/sampling/product/env_hier_product.h, whose EnvProductSampler is its CPU twin). A split node's E F
// becomes the sum of its children's, and its record (gProductRefine, stored after the table) keeps the
// children's 16-bit running sums; productSample descends the records below the chosen node, and productPdf
// multiplies P(j) by each record's P(child), over the deepest node's area.
#ifndef IBLX_LIB_PRODUCT_SAMPLING
#define IBLX_LIB_PRODUCT_SAMPLING
#extension GL_EXT_control_flow_attributes : require
#include "lib/latlong.glsl"
#include "lib/table.glsl"

#ifdef PRODUCT_UNIFORM_GRID
#define PRODUCT_NODES_X PRODUCT_GRID_WIDTH
#define PRODUCT_NODES_Y PRODUCT_GRID_ROWS
// Per cell (row-major): the direction at the centre of its image under env-hier, with the cosine of the
// image's angular radius.
IBLX_TABLE(productGridCenters, 4);
vec4 productNodeCenter(uint j) {
  return tableVec4(productGridCenters, j);
}
vec4 productNodeRect(uint j) {
  uvec2 c = uvec2(j % PRODUCT_NODES_X, j / PRODUCT_NODES_X);
  return vec4(vec2(c), vec2(c + 1u)) /
         vec4(PRODUCT_NODES_X, PRODUCT_NODES_Y, PRODUCT_NODES_X, PRODUCT_NODES_Y);
}
uvec2 productCellOf(vec2 u) {
  return min(uvec2(max(u, vec2(0.0)) * vec2(PRODUCT_NODES_X, PRODUCT_NODES_Y)),
             uvec2(PRODUCT_NODES_X - 1u, PRODUCT_NODES_Y - 1u));
}
#ifdef PRODUCT_TAIL_ENV_OT
#include "lib/env_ot_inverse.glsl"
#else
// The cell of u = env-hier's inverse of wi (its texel's rectangle, and wi's place in the texel).
uvec2 productNodeOf(vec3 wi) {
  ivec2 texel = directionToTexel(wi);
  vec4 rect = hierTexelRect(texel);
  return productCellOf(rect.xy + directionToTexelOffset(wi, texel) * rect.zw);
}
#endif
#else
#define PRODUCT_NODES_X PRODUCT_WIDTH
#define PRODUCT_NODES_Y PRODUCT_ROWS
const uint kProductNodesAtDepth0 = PRODUCT_NODES_X * PRODUCT_NODES_Y;
// Per node (row-major): its rectangle in u (minX, minY, maxX, maxY), and the direction at its centre
// (environment frame) with the cosine of its angular radius.
IBLX_TABLE(productNodeRects, 4);
IBLX_TABLE(productNodeCenters, 4);
vec4 productNodeRect(uint j) {
  return tableVec4(productNodeRects, j);
}
vec4 productNodeCenter(uint j) {
  return tableVec4(productNodeCenters, j);
}
uvec2 productNodeOf(vec3 wi) {
  return uvec2(directionToTexel(wi)) / PRODUCT_TEXELS_PER_NODE;
}
#if PRODUCT_REFINE_DEPTH > 0
#define PRODUCT_REFINED
// Both tables go on with the finer levels, by parent: child c = a + 2 b (cell (2x + a, 2y + b)) of index p
// at depth k is index 4 p + c at depth k + 1 (p the node's own index at depth 0), depth k's entries from
// productDepthOffset(k) on (N, 4 N and 16 N entries: one table, one load whatever the depth).
uint productDepthOffset(uint depth) { return kProductNodesAtDepth0 * ((1u << (2u * depth)) - 1u) / 3u; }
#endif
#endif

#ifdef IBLX_RECORD_SAMPLES
// The last productSample's choice, for the sample record (lib/sample_record.glsl, RECORD_PRODUCT_NODE);
// columns is 0 when it chose nothing.
struct ProductChoice {
  uint node, columns, rows;
  float probability;
  vec4 nodeUv;  // the node on the lat-long map when it is a block of texels, else 0
};
ProductChoice gProductChosen;
#ifdef PRODUCT_UNIFORM_GRID
// A cell of the tail's square: no map rectangle.
vec4 productNodeMapUv(uvec2 cell, uint texels) {
  return vec4(0.0);
}
#else
// The block of texels x texels texels of `cell` on the map.
vec4 productNodeMapUv(uvec2 cell, uint texels) {
  uvec2 size = uvec2(envSize());
  uvec2 first = cell * texels;
  return vec4(vec2(min(first, size)), vec2(min(first + texels, size))) / vec4(size, size);
}
#endif
#endif

const uint kProductNodes = PRODUCT_NODES_X * PRODUCT_NODES_Y;
// The table's running sums, over the rows' totals and within each row, are kept as 16-bit integers: for
// weights w_1..w_n with float running sums r_i and total W, of which m are positive,
//   q_i = min(round(r_i / W (65535 - m)), 65535 - m) + (the positive weights among w_1..w_i),
// so every positive weight keeps at least one step, q_n = 65535 when W > 0 (all 0 when W = 0), and
// P(row y) P(node x | y) = (q_y - q_{y-1}) / 65535 * (q_x - q_{x-1}) / 65535. Sampling and productPdf read
// the same integers, so the pdf stays exact; the quantization halves the stored table, whose loads are what
// a sample of the stored table costs (docs/BENCHMARKS.md, "Product strategies").
const float kProductFullScale = 65535.0;
float gProductColumnSums[kProductNodes];  // per row: its nodes' quantized running sums, as floats
float gProductRowSums[PRODUCT_NODES_Y];   // the rows' quantized running sums, as floats
// Replaces sums[first], ..., sums[first + count - 1], weights of total `total` of which `positive` are > 0,
// by their quantized running sums (see kProductFullScale; the float running sum is summed as `total` was, so
// running / total <= 1).
#define PRODUCT_QUANTIZE(sums, first, count, total, positive)                                            \
  {                                                                                                      \
    float steps = kProductFullScale - float(positive), running = 0.0;                                    \
    uint counted = 0u;                                                                                   \
    [[dont_unroll]] for (uint i = 0u; i < count; ++i) {                                                  \
      float weight = sums[first + i];                                                                    \
      running += weight;                                                                                 \
      counted += weight > 0.0 ? 1u : 0u;                                                                 \
      sums[first + i] = total > 0.0 ? min(round(running / total * steps), steps) + float(counted) : 0.0; \
    }                                                                                                    \
  }
#ifdef PRODUCT_REFINED
// The refinement's block (productRefineWords, engine/sampling/product/env_hier_product.h): per node a 4-bit
// field, its record + 1 (0: not split), eight to a word; then two words per record: the children's running
// sums q_1 | q_2 << 16, and q_3 | (the mask of children split again) << 16 | (the first one's record) << 20
// (q_4 = kProductFullScale). Records 0 .. kProductRefinedNodes - 1 are the split nodes', the rest their
// children's, by parent and child.
const uint kProductRefinedNodes = 15u, kProductRefinedChildren = 16u;
const uint kProductSlotWords = (kProductNodes + 7u) / 8u;
const uint kProductRecords = kProductRefinedNodes + (PRODUCT_REFINE_DEPTH > 1 ? kProductRefinedChildren : 0u);
const uint kProductRefineWords = kProductSlotWords + 2u * kProductRecords;
uint gProductRefine[kProductRefineWords];
// Whether this pixel's table has records (productLobeNarrowerThanNode): stored as one word before the block,
// so a pixel without them reads no record and copies no block.
bool gProductSplit = false;
#endif
#ifdef PRODUCT_TABLE_BINDING
// PRODUCT_TABLE_STRIDE words per pixel, pixels row-major, PRODUCT_TABLE_PIXELS_PER_CHUNK pixels per buffer:
// integrate.comp's invocation (x, y) shades pixel (x, y) in the image mode that binds these buffers. A
// pixel's block holds the rows' running sums first, so a dispatch of few samples reads them from one cache
// line, then each row's, two per word (the even one in the low half; an odd count's padding half is 0xffff).
layout(std430, set = 0, binding = PRODUCT_TABLE_BINDING) buffer ProductTableData0 {
  uint productTables0[];
};
#if PRODUCT_TABLE_CHUNKS > 1
layout(std430, set = 0, binding = PRODUCT_TABLE_BINDING + 1) buffer ProductTableData1 {
  uint productTables1[];
};
#endif
#if PRODUCT_TABLE_CHUNKS > 2
layout(std430, set = 0, binding = PRODUCT_TABLE_BINDING + 2) buffer ProductTableData2 {
  uint productTables2[];
};
#endif
#if PRODUCT_TABLE_CHUNKS > 3
layout(std430, set = 0, binding = PRODUCT_TABLE_BINDING + 3) buffer ProductTableData3 {
  uint productTables3[];
};
#endif
#if PRODUCT_TABLE_CHUNKS > 4
#error "PRODUCT_TABLE_CHUNKS above kProductTableMaxChunks (engine/scene/kernel_prelude.h)"
#endif
// Words of the rows' sums and of one row's; the builders check that a pixel's block fits
// PRODUCT_TABLE_STRIDE (productTableWords, engine/sampling/product/env_hier_product.h).
const uint kProductRowSumWords = (PRODUCT_NODES_Y + 1u) / 2u;
const uint kProductRowWords = (PRODUCT_NODES_X + 1u) / 2u;
const uint kProductTableWords =
    kProductRowSumWords + PRODUCT_NODES_Y * kProductRowWords;  // then the refinement
// The pixel's place: its chunk and the offset of its block there (set by productPrepare).
uint gProductTableChunk = 0u, gProductTableAt = 0u;
// PRODUCT_TABLE_ON_CHUNK(OP) runs OP(the pixel's chunk's array): the one chain over the chunks.
#if PRODUCT_TABLE_CHUNKS > 1
#define PRODUCT_TABLE_CHUNK_1(OP)      \
  else if (gProductTableChunk == 1u) { \
    OP(productTables1)                 \
  }
#else
#define PRODUCT_TABLE_CHUNK_1(OP)
#endif
#if PRODUCT_TABLE_CHUNKS > 2
#define PRODUCT_TABLE_CHUNK_2(OP)      \
  else if (gProductTableChunk == 2u) { \
    OP(productTables2)                 \
  }
#else
#define PRODUCT_TABLE_CHUNK_2(OP)
#endif
#if PRODUCT_TABLE_CHUNKS > 3
#define PRODUCT_TABLE_CHUNK_3(OP)      \
  else if (gProductTableChunk == 3u) { \
    OP(productTables3)                 \
  }
#else
#define PRODUCT_TABLE_CHUNK_3(OP)
#endif
#define PRODUCT_TABLE_ON_CHUNK(OP) \
  if (gProductTableChunk == 0u) {  \
    OP(productTables0)             \
  }                                \
  PRODUCT_TABLE_CHUNK_1(OP) PRODUCT_TABLE_CHUNK_2(OP) PRODUCT_TABLE_CHUNK_3(OP)

#define PRODUCT_TABLE_READ(table) word = table[at];
// The word at `at` of the pixel's block.
uint productStoredWord(uint at) {
  uint word = 0u;
  at += gProductTableAt;
  PRODUCT_TABLE_ON_CHUNK(PRODUCT_TABLE_READ)
  return word;
}
// Row y's quantized running sum up to node j.
float productStoredSum(uint j) {
  uint y = j / PRODUCT_NODES_X, x = j - y * PRODUCT_NODES_X;
  uint word = productStoredWord(kProductRowSumWords + y * kProductRowWords + (x >> 1u));
  return float(bitfieldExtract(word, int((x & 1u) * 16u), 16));
}
// PRODUCT_STORE_PAIRS(table, at, sums, first, count, words): `count` private sums from sums[first] on, packed
// into `words` words of the pixel's block from `at` on.
#define PRODUCT_STORE_PAIRS(table, at, sums, first, count, words)                 \
  [[dont_unroll]] for (uint w = 0u; w < words; ++w) {                             \
    uint high = 2u * w + 1u < count ? uint(sums[first + 2u * w + 1u]) : 0xffffu;  \
    table[gProductTableAt + at + w] = uint(sums[first + 2u * w]) | (high << 16u); \
  }
#define PRODUCT_LOAD_PAIRS(table, at, sums, first, count, words)             \
  [[dont_unroll]] for (uint w = 0u; w < words; ++w) {                        \
    uint word = table[gProductTableAt + at + w];                             \
    sums[first + 2u * w] = float(word & 0xffffu);                            \
    if (2u * w + 1u < count) sums[first + 2u * w + 1u] = float(word >> 16u); \
  }
#define PRODUCT_TABLE_STORE(table)                                                             \
  PRODUCT_STORE_PAIRS(table, 0u, gProductRowSums, 0u, PRODUCT_NODES_Y, kProductRowSumWords)    \
  [[dont_unroll]] for (uint y = 0u; y < PRODUCT_NODES_Y; ++y) {                                \
    PRODUCT_STORE_PAIRS(table, kProductRowSumWords + y * kProductRowWords, gProductColumnSums, \
                        y * PRODUCT_NODES_X, PRODUCT_NODES_X, kProductRowWords)                \
  }
#define PRODUCT_TABLE_LOAD(table)                                                             \
  [[dont_unroll]] for (uint y = 0u; y < PRODUCT_NODES_Y; ++y) {                               \
    PRODUCT_LOAD_PAIRS(table, kProductRowSumWords + y * kProductRowWords, gProductColumnSums, \
                       y * PRODUCT_NODES_X, PRODUCT_NODES_X, kProductRowWords)                \
  }
#define PRODUCT_TABLE_LOAD_ROW_SUMS(table) \
  PRODUCT_LOAD_PAIRS(table, 0u, gProductRowSums, 0u, PRODUCT_NODES_Y, kProductRowSumWords)
#ifdef PRODUCT_REFINED
#define PRODUCT_REFINE_STORE(table)                                                       \
  table[gProductTableAt + kProductTableWords] = gProductSplit ? 1u : 0u;                  \
  if (gProductSplit) {                                                                    \
    [[dont_unroll]] for (uint w = 0u; w < kProductRefineWords; ++w) {                     \
      table[gProductTableAt + kProductTableWords + 1u + w] = gProductRefine[w];           \
    }                                                                                     \
  }
#define PRODUCT_REFINE_LOAD_FLAG(table) gProductSplit = table[gProductTableAt + kProductTableWords] != 0u;
#else
#define PRODUCT_REFINE_STORE(table)
#define PRODUCT_REFINE_LOAD_FLAG(table)
#endif
void productTableLocate(uvec2 pixel) {
  uint index = pixel.y * frame.width + pixel.x;
  gProductTableChunk = index / PRODUCT_TABLE_PIXELS_PER_CHUNK;
  gProductTableAt = (index - gProductTableChunk * PRODUCT_TABLE_PIXELS_PER_CHUNK) * PRODUCT_TABLE_STRIDE;
}
// Stores the private table into the pixel's chunk (the product-table kernel), or loads its rows' sums and,
// with `rows`, every row's (the integrator).
#ifdef PRODUCT_TABLE_BUILD
void productTableStore() {
  PRODUCT_TABLE_ON_CHUNK(PRODUCT_TABLE_STORE)
  PRODUCT_TABLE_ON_CHUNK(PRODUCT_REFINE_STORE)
}
#else
void productTableLoad(bool rows) {
  PRODUCT_TABLE_ON_CHUNK(PRODUCT_TABLE_LOAD_ROW_SUMS)
  PRODUCT_TABLE_ON_CHUNK(PRODUCT_REFINE_LOAD_FLAG)
  if (rows) {
    PRODUCT_TABLE_ON_CHUNK(PRODUCT_TABLE_LOAD)
  }
}
#endif
// The node of row y whose quantized interval [start, end) holds t in [0, kProductFullScale), from the
// stored row: a binary search over the row's words by their high halves (the last word's is above every
// target: the row's last running sum 65535, or an odd row's padding), then the word's low half decides.
// Each step is one load, and the interval's ends come from the words it loaded: the high half of the last
// word found below t, and the word the search ends on.
uint productStoredChoice(uint y, float t, out float start, out float end) {
  uint first = kProductRowSumWords + y * kProductRowWords;
  uint lower = 0u, len = kProductRowWords - 1u, upperWord = 0u;
  start = 0.0;
  while (len > 0u) {
    uint step = len >> 1u;
    uint word = productStoredWord(first + lower + step);
    float high = float(word >> 16u);
    if (high <= t) {
      start = high;
      lower += step + 1u;
      len -= step + 1u;
    } else {
      upperWord = word;
      len = step;
    }
  }
  // The search loaded the word it ends on unless it ends on the row's last word, which it never compares.
  if (lower == kProductRowWords - 1u) upperWord = productStoredWord(first + lower);
  float low = float(upperWord & 0xffffu);
  bool lowBelow = low <= t;
  if (lowBelow) start = low;
  end = lowBelow ? float(upperWord >> 16u) : low;
  return 2u * lower + (lowBelow ? 1u : 0u);
}
// A dispatch of this many samples or more copies the stored table into private memory once and scans it
// there (branch-free selects that vectorise across invocations); one of fewer reads only the entries its
// samples' searches visit (docs/BENCHMARKS.md, "Product strategies").
const uint kProductCopyMinSamples = 32u;
#endif

bool gProductReadStored = false;  // this dispatch samples from the stored table, not a private copy
// A row's quantized running sum up to node j, from the stored or the private table.
float productColumnSum(uint j) {
#ifdef PRODUCT_TABLE_BINDING
  if (gProductReadStored) return productStoredSum(j);
#endif
  return gProductColumnSums[j];
}
#ifdef PRODUCT_REFINED
// Word i of the refinement's block: with stored tables always from the buffer (the product-table kernel
// stored it, and a record is read only by a sample that descends into a split node, so a dispatch copies
// none of it), else from the private table.
uint productRefineWord(uint i) {
#ifdef PRODUCT_TABLE_BINDING
  return productStoredWord(kProductTableWords + 1u + i);
#else
  return gProductRefine[i];
#endif
}
// Node j's record + 1, 0 when it is not split.
uint productRecordOf(uint j) { return bitfieldExtract(productRefineWord(j >> 3u), int((j & 7u) * 4u), 4); }
uvec2 productRecordWords(uint record) {
  uint at = kProductSlotWords + 2u * record;
  return uvec2(productRefineWord(at), productRefineWord(at + 1u));
}
// Child c's quantized interval [start, end) in a record's words.
void productChildInterval(uvec2 words, uint c, out float start, out float end) {
  float q1 = float(words.x & 0xffffu), q2 = float(words.x >> 16u), q3 = float(words.y & 0xffffu);
  start = c == 0u ? 0.0 : (c == 1u ? q1 : (c == 2u ? q2 : q3));
  end = c == 0u ? q1 : (c == 1u ? q2 : (c == 2u ? q3 : kProductFullScale));
}
// The record of child c of the record whose words these are + 1, 0 when c is not split.
uint productChildRecord(uvec2 words, uint c) {
  uint mask = (words.y >> 16u) & 0xfu;
  return ((mask >> c) & 1u) != 0u ? (words.y >> 20u) + bitCount(mask & ((1u << c) - 1u)) + 1u : 0u;
}
// The rectangle in u of index p at depth 0, 1 or 2 (by parent, as the tables are ordered).
vec4 productRectAt(uint depth, uint p) { return tableVec4(productNodeRects, productDepthOffset(depth) + p); }
vec4 productCenterAt(uint depth, uint p) { return tableVec4(productNodeCenters, productDepthOffset(depth) + p); }
#endif

float productNodeArea(uint j) {
  vec4 r = productNodeRect(j);
  return (r.z - r.x) * (r.w - r.y);
}

// The direction of the cap (centre, cosRadius) closest to `towards`: the CPU twin is closestDirectionInCap.
vec3 productNodeDirection(vec3 centre, float cosRadius, vec3 towards) {
  float cosAngle = dot(centre, towards);
  if (cosAngle >= cosRadius) return towards;
  vec3 tangent = towards - centre * cosAngle;
  float len = length(tangent);
  if (!(len > 1e-6)) return centre;
  return centre * cosRadius + tangent * (sqrt(max(0.0, 1.0 - cosRadius * cosRadius)) / len);
}

// E F of a node: its rectangle's area E times F = mean_rgb(f) cos at its cap's direction closest to the
// mirror direction of wo (local frame); 0 for an empty node.
float productNodeValue(vec4 rect, vec4 centre, Shading s, vec3 mirror) {
  float area = (rect.z - rect.x) * (rect.w - rect.y);
  if (!(area > 0.0)) return 0.0;
  vec3 d = normalize(productNodeDirection(toLocal(s, centre.xyz), centre.w, mirror));
  if (!(d.z > 0.0)) return 0.0;
  vec3 f = brdfEval(d, s.woLocal);
  float fCos = (f.r + f.g + f.b) / 3.0 * d.z;
  return fCos > 0.0 && !isinf(fCos) ? area * fCos
                                    : 0.0;  // a non-finite or negative lobe value: no preference
}

#ifdef PRODUCT_REFINED
// Keeps the `capacity` largest positive values seen, largest first, an earlier one first among equal ones
// (the CPU twin's largestPositive).
#define PRODUCT_KEEP_LARGEST(values, indices, count, capacity, value, index) \
  if (value > 0.0 && (count < capacity || value > values[capacity - 1u])) {  \
    uint at = min(count, capacity - 1u);                                     \
    [[dont_unroll]] while (at > 0u && values[at - 1u] < value) {             \
      values[at] = values[at - 1u];                                          \
      indices[at] = indices[at - 1u];                                        \
      --at;                                                                  \
    }                                                                        \
    values[at] = value;                                                      \
    indices[at] = index;                                                     \
    count = min(count + 1u, capacity);                                       \
  }

// Writes record r: the children's weights w_c = (1 - d) e_c / sum e + d E_c / sum E (E_c / sum E without a
// lobe value), quantized, with the mask of children split again and the first one's record.
void productWriteRecord(uint r, vec4 areas, vec4 values, uint mask, uint first) {
  float sumArea = ((areas.x + areas.y) + areas.z) + areas.w,
        sumValue = ((values.x + values.y) + values.z) + values.w;
  vec4 w = sumArea > 0.0
               ? (sumValue > 0.0
                      ? (1.0 - PRODUCT_DEFENSIVE) * values / sumValue + PRODUCT_DEFENSIVE * areas / sumArea
                      : areas / sumArea)
               : vec4(0.0);
  float sums[4] = float[4](w.x, w.y, w.z, w.w);
  float total = ((w.x + w.y) + w.z) + w.w;
  uint positive = uint(w.x > 0.0) + uint(w.y > 0.0) + uint(w.z > 0.0) + uint(w.w > 0.0);
  PRODUCT_QUANTIZE(sums, 0u, 4u, total, positive)
  uint at = kProductSlotWords + 2u * r;
  gProductRefine[at] = uint(sums[0]) | (uint(sums[1]) << 16u);
  gProductRefine[at + 1u] = uint(sums[2]) | (mask << 16u) | (first << 20u);
}

// Whether the lobe falls below half its peak within one node's width (2 pi / PRODUCT_NODES_X) of the mirror
// direction, across it: only then is the split worth its BRDF evaluations and its record's loads per sample
// (a wider lobe is already resolved by the nodes: docs/RESULTS.md, "The most probable nodes refined"). Either
// answer leaves an exact sampler (the refined one or the one-level table); an undefined peak refines.
bool productLobeNarrowerThanNode(Shading s, vec3 mirror) {
  if (!(mirror.z > 0.0)) return true;
  vec3 across = abs(mirror.z) < 0.999 ? normalize(vec3(-mirror.y, mirror.x, 0.0)) : vec3(1.0, 0.0, 0.0);
  float angle = 2.0 * kPi / float(PRODUCT_NODES_X);
  vec3 probe = cos(angle) * mirror + sin(angle) * across;  // turned parallel to the surface: probe.z > 0
  vec3 peak = brdfEval(mirror, s.woLocal), off = brdfEval(probe, s.woLocal);
  return !((off.r + off.g + off.b) * probe.z >= 0.5 * (peak.r + peak.g + peak.b) * mirror.z);
}

// Splits the nodes of largest E F (gProductColumnSums) into their children and the largest children once
// more, revalues the split ones by their children's sum and writes the records (gProductRefine).
void productRefine(Shading s, vec3 mirror) {
  uint split[kProductRefinedNodes];
  float splitValue[kProductRefinedNodes];
  uint splitCount = 0u;
  [[dont_unroll]] for (uint j = 0u; j < kProductNodes; ++j) {
    float value = gProductColumnSums[j];
    PRODUCT_KEEP_LARGEST(splitValue, split, splitCount, kProductRefinedNodes, value, j)
  }
  vec4 childValues[kProductRefinedNodes], childAreas[kProductRefinedNodes];
  [[dont_unroll]] for (uint n = 0u; n < splitCount; ++n) [[dont_unroll]] for (uint c = 0u; c < 4u; ++c) {
    uint p = 4u * split[n] + c;
    vec4 rect = productRectAt(1u, p);
    childAreas[n][c] = (rect.z - rect.x) * (rect.w - rect.y);
    childValues[n][c] = productNodeValue(rect, productCenterAt(1u, p), s, mirror);
  }
  [[dont_unroll]] for (uint w = 0u; w < kProductRefineWords; ++w) gProductRefine[w] = 0u;
  uint masks[kProductRefinedNodes], firsts[kProductRefinedNodes];
  [[dont_unroll]] for (uint n = 0u; n < kProductRefinedNodes; ++n) masks[n] = firsts[n] = 0u;
#if PRODUCT_REFINE_DEPTH > 1
  uint again[kProductRefinedChildren];
  float againValue[kProductRefinedChildren];
  uint againCount = 0u;
  [[dont_unroll]] for (uint k = 0u; k < 4u * splitCount; ++k) {
    float value = childValues[k >> 2u][k & 3u];
    PRODUCT_KEEP_LARGEST(againValue, again, againCount, kProductRefinedChildren, value, k)
  }
  uvec2 chosen = uvec2(0u);  // by child k = 4 n + c < 60
  [[dont_unroll]] for (uint i = 0u; i < againCount; ++i) chosen[again[i] >> 5u] |= 1u << (again[i] & 31u);
  uint record = kProductRefinedNodes;  // the children's records, by parent and child
  [[dont_unroll]] for (uint k = 0u; k < 4u * splitCount; ++k) {
    if ((chosen[k >> 5u] & (1u << (k & 31u))) == 0u) continue;
    uint n = k >> 2u, c = k & 3u;
    vec4 areas, values;
    [[dont_unroll]] for (uint g = 0u; g < 4u; ++g) {
      uint p = 4u * (4u * split[n] + c) + g;
      vec4 rect = productRectAt(2u, p);
      areas[g] = (rect.z - rect.x) * (rect.w - rect.y);
      values[g] = productNodeValue(rect, productCenterAt(2u, p), s, mirror);
    }
    childValues[n][c] = ((values.x + values.y) + values.z) + values.w;  // revalued by the finer look
    if (masks[n] == 0u) firsts[n] = record;
    masks[n] |= 1u << c;
    productWriteRecord(record, areas, values, 0u, 0u);
    ++record;
  }
#endif
  [[dont_unroll]] for (uint n = 0u; n < splitCount; ++n) {
    vec4 values = childValues[n];
    gProductColumnSums[split[n]] = ((values.x + values.y) + values.z) + values.w;
    productWriteRecord(n, childAreas[n], values, masks[n], firsts[n]);
    gProductRefine[split[n] >> 3u] |= (n + 1u) << ((split[n] & 7u) * 4u);
  }
}
#endif

void productBuildTable(Shading s) {
  vec3 mirror = vec3(-s.woLocal.xy, s.woLocal.z);  // the mirror direction of wo about n, local frame
  [[dont_unroll]] for (uint j = 0u; j < kProductNodes; ++j) gProductColumnSums[j] =
      productNodeValue(productNodeRect(j), productNodeCenter(j), s, mirror);
#ifdef PRODUCT_REFINED
  gProductSplit = productLobeNarrowerThanNode(s, mirror);
  if (gProductSplit) productRefine(s, mirror);
#endif
  float sumEF = 0.0;
  [[dont_unroll]] for (uint j = 0u; j < kProductNodes; ++j) sumEF += gProductColumnSums[j];
  float envShare = sumEF > 0.0 && !isinf(sumEF) ? PRODUCT_DEFENSIVE : 1.0;
  float productScale = envShare < 1.0 ? (1.0 - envShare) / sumEF : 0.0;
  // Per row: the weights, their total and count of positive ones, then the row's quantized running sums;
  // the row totals go through the same quantization in gProductRowSums.
  float rowsTotal = 0.0;
  uint positiveRows = 0u;
  [[dont_unroll]] for (uint y = 0u; y < PRODUCT_NODES_Y; ++y) {
    float total = 0.0;
    uint positive = 0u;
    [[dont_unroll]] for (uint x = 0u; x < PRODUCT_NODES_X; ++x) {
      uint j = y * PRODUCT_NODES_X + x;
      float weight = productScale * gProductColumnSums[j] + envShare * productNodeArea(j);
      gProductColumnSums[j] = weight;
      total += weight;
      positive += weight > 0.0 ? 1u : 0u;
    }
    PRODUCT_QUANTIZE(gProductColumnSums, y * PRODUCT_NODES_X, PRODUCT_NODES_X, total, positive)
    gProductRowSums[y] = total;
    rowsTotal += total;
    positiveRows += total > 0.0 ? 1u : 0u;
  }
  PRODUCT_QUANTIZE(gProductRowSums, 0u, PRODUCT_NODES_Y, rowsTotal, positiveRows)
}

void productPrepare(Shading s) {
#ifdef PRODUCT_TABLE_BINDING
  productTableLocate(gl_GlobalInvocationID.xy);
#ifdef PRODUCT_TABLE_BUILD
  productBuildTable(s);
  productTableStore();
#else
  gProductReadStored = frame.samplesPerPass < kProductCopyMinSamples;
  productTableLoad(!gProductReadStored);
#endif
#else
  productBuildTable(s);
#endif
}

// P(node (x, y)) from the running sums, as sampling chooses it; 0 for an empty node, row or table.
float productNodeProbability(uint x, uint y) {
  float total = gProductRowSums[PRODUCT_NODES_Y - 1u];
  uint base = y * PRODUCT_NODES_X;
  float rowWidth = gProductRowSums[y] - (y == 0u ? 0.0 : gProductRowSums[y - 1u]);
  float columnWidth = productColumnSum(base + x) - (x == 0u ? 0.0 : productColumnSum(base + x - 1u));
  return total > 0.0 ? (rowWidth / total) * (columnWidth / kProductFullScale) : 0.0;
}

#ifdef PRODUCT_UNIFORM_GRID
// h(u) = P(cell of u) / E(cell of u), the head warp's density on the grid.
float productHeadDensity(vec2 u) {
  uvec2 c = productCellOf(u);
  float area = productNodeArea(c.y * PRODUCT_NODES_X + c.x);
  return area > 0.0 ? productNodeProbability(c.x, c.y) / area : 0.0;
}
#endif

vec3 productSample(vec2 u, Shading s, out float pdf, out vec3 radiance) {
  pdf = 0.0;
  radiance = vec3(0.0);
#ifdef IBLX_RECORD_SAMPLES
  gProductChosen.columns = 0u;
#endif
  float total = gProductRowSums[PRODUCT_NODES_Y - 1u];
  if (!(total > 0.0)) return vec3(0.0, 1.0, 0.0);
  // The first row whose running sum exceeds u.y * total: a row of zero width is never chosen.
  float ty = u.y * total;
  uint y = 0u;
  for (uint k = 0u; k + 1u < PRODUCT_NODES_Y; ++k) y += gProductRowSums[k] <= ty ? 1u : 0u;
  float rowStart = y == 0u ? 0.0 : gProductRowSums[y - 1u], rowWidth = gProductRowSums[y] - rowStart;
  uint base = y * PRODUCT_NODES_X;
  float tx = u.x * kProductFullScale;
  uint x = 0u;
  float columnStart, columnWidth;
#ifdef PRODUCT_TABLE_BINDING
  if (gProductReadStored) {
    float columnEnd;
    x = productStoredChoice(y, tx, columnStart, columnEnd);
    columnWidth = columnEnd - columnStart;
  } else
#endif
  {
    for (uint k = 0u; k + 1u < PRODUCT_NODES_X; ++k) x += gProductColumnSums[base + k] <= tx ? 1u : 0u;
    columnStart = x == 0u ? 0.0 : gProductColumnSums[base + x - 1u];
    columnWidth = gProductColumnSums[base + x] - columnStart;
  }
  if (!(rowWidth > 0.0) || !(columnWidth > 0.0)) return vec3(0.0, 1.0, 0.0);  // u on a float edge
  vec2 v = clamp(vec2((tx - columnStart) / columnWidth, (ty - rowStart) / rowWidth), vec2(0.0),
                 vec2(kOneMinusEpsilon));
  uint j = base + x;
  // P(j) as productNodeProbability computes it, from the widths found above.
  float probability = (rowWidth / total) * (columnWidth / kProductFullScale);
  uint depth = 0u, index = j;  // the deepest node chosen: its depth and its index by parent
  uvec2 cell = uvec2(x, y);    // and its cell at its depth
#ifdef PRODUCT_REFINED
  // The records below the node: the first split reads v.x, the second v.y, each rescaled inside the child.
  // Behind the pixel's flag, and without a return inside the loop: a pixel without records runs none of it.
  vec4 r;
  if (gProductSplit) {
    [[dont_unroll]] for (uint record = productRecordOf(j); record != 0u;) {
      uvec2 words = productRecordWords(record - 1u);
      float t = (depth == 0u ? v.x : v.y) * kProductFullScale;
      uint c = (float(words.x & 0xffffu) <= t ? 1u : 0u) + (float(words.x >> 16u) <= t ? 1u : 0u) +
               (float(words.y & 0xffffu) <= t ? 1u : 0u);
      float start, end;
      productChildInterval(words, c, start, end);
      probability *= max(end - start, 0.0) / kProductFullScale;  // 0 for t on a float edge: pdf 0
      float inChild = clamp((t - start) / max(end - start, 1.0), 0.0, kOneMinusEpsilon);
      if (depth == 0u)
        v.x = inChild;
      else
        v.y = inChild;
      record = productChildRecord(words, c);
      index = 4u * index + c;
      cell = 2u * cell + uvec2(c & 1u, c >> 1u);
      ++depth;
    }
  }
  r = productRectAt(depth, index);
#else
  vec4 r = productNodeRect(j);
#endif
  // Inside the node's rectangle, a float set: at most one float step below its upper edges (which are > 0).
  vec2 below = uintBitsToFloat(floatBitsToUint(r.zw) - 1u);
  vec2 inNode = clamp(r.xy + v * (r.zw - r.xy), r.xy, below);
  float envDensity;
  vec3 wi = envSample(inNode, s.n, envDensity, radiance);
  float area = (r.z - r.x) * (r.w - r.y);
  pdf = envDensity > 0.0 && area > 0.0 ? probability / area * envDensity : 0.0;
#ifdef IBLX_RECORD_SAMPLES
  // The deepest node chosen, row-major among its level's cells (2^depth times the table's across).
  uint columns = PRODUCT_NODES_X << depth, rows = PRODUCT_NODES_Y;
#ifdef PRODUCT_REFINED
  uint texels = PRODUCT_TEXELS_PER_NODE >> depth;
  rows = (uint(envSize().y) + texels - 1u) / texels;
#else
  uint texels = 1u;
#ifndef PRODUCT_UNIFORM_GRID
  texels = PRODUCT_TEXELS_PER_NODE;
#endif
#endif
  gProductChosen =
      ProductChoice(cell.y * columns + cell.x, columns, rows, probability, productNodeMapUv(cell, texels));
#endif
#ifdef PRODUCT_TAIL_ENV_OT
  // A split sun's texel: the branch taken (the sun row when u.y reached it, env-ot's row search) keeps the
  // chosen cell's density, the other branch's preimage is located.
  ivec2 texel = directionToTexel(wi);
  vec2 q = envOtBranchPdfs(texel);
  if (pdf > 0.0 && q.y > 0.0) {
    bool sunRow = inNode.y >= tableFloat(envOtRowCdf, ENV_OT_GRID);
    vec2 uMap, uSun;
    bool hasMap, hasSun;
    envOtPreimages(wi, texel, uMap, hasMap, uSun, hasSun);
    float head = probability / area;
    float other = sunRow ? (hasMap ? productHeadDensity(uMap) * q.x : 0.0)
                         : (hasSun ? productHeadDensity(uSun) * q.y : 0.0);
    pdf = head * (sunRow ? q.y : q.x) + other;
  }
#endif
  return wi;
}

#ifdef PRODUCT_TAIL_ENV_OT
// h(u_map) q_map + h(u_sun) q_sun (engine/sampling/product/env_ot_product.h).
float productPdf(vec3 wi, Shading s) {
  ivec2 texel = directionToTexel(wi);
  vec2 q = envOtBranchPdfs(texel);
  vec2 uMap, uSun;
  bool hasMap, hasSun;
  envOtPreimages(wi, texel, uMap, hasMap, uSun, hasSun);
  return (hasMap && q.x > 0.0 ? productHeadDensity(uMap) * q.x : 0.0) +
         (hasSun && q.y > 0.0 ? productHeadDensity(uSun) * q.y : 0.0);
}
#else
float productPdf(vec3 wi, Shading s) {
#ifdef PRODUCT_REFINED
  uvec2 texel = uvec2(directionToTexel(wi));
  uvec2 node = texel / PRODUCT_TEXELS_PER_NODE;
#else
  uvec2 node = productNodeOf(wi);
#endif
  if (node.x >= PRODUCT_NODES_X || node.y >= PRODUCT_NODES_Y) return 0.0;
  uint j = node.y * PRODUCT_NODES_X + node.x;
  float probability = productNodeProbability(node.x, node.y);
#ifdef PRODUCT_REFINED
  // Each record below the node (behind the pixel's flag): the child holding wi's texel, and its P(child).
  uint depth = 0u, index = j;
  if (gProductSplit) {
    [[dont_unroll]] for (uint record = productRecordOf(j); record != 0u;) {
      uvec2 words = productRecordWords(record - 1u);
      uvec2 childCell = texel / (PRODUCT_TEXELS_PER_NODE >> (depth + 1u));
      uint c = (childCell.x & 1u) | ((childCell.y & 1u) << 1u);
      float start, end;
      productChildInterval(words, c, start, end);
      probability *= (end - start) / kProductFullScale;
      record = productChildRecord(words, c);
      index = 4u * index + c;
      ++depth;
    }
  }
  vec4 r = productRectAt(depth, index);
  float area = (r.z - r.x) * (r.w - r.y);
#else
  float area = productNodeArea(j);
#endif
  return area > 0.0 ? probability / area * envPdf(wi, s.n) : 0.0;
}
#endif
#endif
