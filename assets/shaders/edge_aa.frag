// Post-process edge anti-aliasing of a one-sample image (the default; multisampling costs
// llvmpipe a shaded fragment for every covered sample of every box, hidden or not).
//
// For each pixel: if its 4-neighbourhood has little luma contrast it is copied unchanged.
// Otherwise the edge through it is classified as horizontal or vertical, the neighbour
// across the edge with the larger contrast is chosen, and the edge is followed both ways on
// the line between the two pixels (where a bilinear sample averages them) until the
// average departs from the edge's luma, i.e. the end of the stair step. A staircase edge is
// a line crossing each step in the middle, so a pixel near the end of a step where the
// other side continues is partly covered by the other side: it is blended towards its
// neighbour by 0.5 at the step's end, falling to 0 at the step's middle. Isolated
// one-pixel features get a smaller blend from the 3x3 neighbourhood. Deterministic: fixed
// steps, no randomness.
//
// Compiled twice. With EDGE_DETECT defined it only finds the pixels to work on (discarding
// the others), and the renderer marks them in the stencil buffer; the full pass then runs on
// marked pixels only (llvmpipe tests stencil before shading, and would otherwise run the
// edge search below for every pixel).
uniform sampler2D u_image;  // the one-sample image (linear filtering, clamped)
uniform ivec2 u_size;       // its size, pixels
uniform vec2 u_origin;      // window position of its lower-left corner, pixels

out vec4 frag_color;

const float kMinContrast = 0.035;  // luma range below which nothing is done
const float kRelContrast = 0.125;  // ... or below this fraction of the brightest luma
const float kSubpixel = 0.5;       // largest blend of an isolated one-pixel feature
const int kSteps = 10;
const float kDistance[kSteps] =
    float[kSteps](1.0, 2.0, 3.0, 4.0, 5.0, 6.5, 8.0, 10.0, 13.0, 17.0);  // pixels

float luma_of(vec3 c) {
  return dot(c, vec3(0.299, 0.587, 0.114));
}

vec3 fetch(ivec2 p) {
  return texelFetch(u_image, clamp(p, ivec2(0), u_size - 1), 0).rgb;
}

void main() {
  vec2 texel = 1.0 / vec2(u_size);
  ivec2 p = ivec2(gl_FragCoord.xy - u_origin);
  vec3 centre = fetch(p);
  float lc = luma_of(centre);
  float ln = luma_of(fetch(p + ivec2(0, 1)));
  float ls = luma_of(fetch(p + ivec2(0, -1)));
  float le = luma_of(fetch(p + ivec2(1, 0)));
  float lw = luma_of(fetch(p + ivec2(-1, 0)));
  float lo = min(lc, min(min(ln, ls), min(le, lw)));
  float hi = max(lc, max(max(ln, ls), max(le, lw)));
  float range = hi - lo;
#ifdef EDGE_DETECT
  if (range < max(kMinContrast, hi * kRelContrast)) discard;
  frag_color = vec4(centre, 1.0);
#else
  if (range < max(kMinContrast, hi * kRelContrast)) {
    frag_color = vec4(centre, 1.0);
    return;
  }
  float lne = luma_of(fetch(p + ivec2(1, 1)));
  float lnw = luma_of(fetch(p + ivec2(-1, 1)));
  float lse = luma_of(fetch(p + ivec2(1, -1)));
  float lsw = luma_of(fetch(p + ivec2(-1, -1)));

  // A horizontal edge changes luma along y: compare second differences in y and in x.
  float dyy = abs(lnw + lsw - 2.0 * lw) + 2.0 * abs(ln + ls - 2.0 * lc) + abs(lne + lse - 2.0 * le);
  float dxx = abs(lnw + lne - 2.0 * ln) + 2.0 * abs(lw + le - 2.0 * lc) + abs(lsw + lse - 2.0 * ls);
  bool horizontal = dyy >= dxx;
  float l_neg = horizontal ? ls : lw;
  float l_pos = horizontal ? ln : le;
  float g_neg = abs(l_neg - lc);
  float g_pos = abs(l_pos - lc);
  vec2 across = horizontal ? vec2(0.0, texel.y) : vec2(texel.x, 0.0);
  float l_other = l_pos;
  if (g_neg >= g_pos) {
    across = -across;
    l_other = l_neg;
  }
  float edge_luma = 0.5 * (lc + l_other);
  float threshold = 0.25 * max(g_neg, g_pos);

  // Follow the edge both ways.
  vec2 uv = (vec2(p) + 0.5) * texel;
  vec2 start = uv + 0.5 * across;
  vec2 along = horizontal ? vec2(texel.x, 0.0) : vec2(0.0, texel.y);
  float d_neg = kDistance[kSteps - 1], d_pos = kDistance[kSteps - 1];
  float end_neg = edge_luma, end_pos = edge_luma;
  bool open_neg = true, open_pos = true;
  for (int i = 0; i < kSteps; ++i) {
    if (open_neg) {
      end_neg = luma_of(textureLod(u_image, start - along * kDistance[i], 0.0).rgb);
      if (abs(end_neg - edge_luma) >= threshold) {
        open_neg = false;
        d_neg = kDistance[i];
      }
    }
    if (open_pos) {
      end_pos = luma_of(textureLod(u_image, start + along * kDistance[i], 0.0).rgb);
      if (abs(end_pos - edge_luma) >= threshold) {
        open_pos = false;
        d_pos = kDistance[i];
      }
    }
    if (!open_neg && !open_pos) break;
  }
  // The nearer end decides: blend only if the luma there lies on the other side of the
  // edge's luma from this pixel (the step ends by the other side continuing).
  float d_near = min(d_neg, d_pos);
  float end_luma = d_neg < d_pos ? end_neg : end_pos;
  bool mixes = (end_luma < edge_luma) != (lc < edge_luma);
  float blend = mixes ? 0.5 - d_near / (d_neg + d_pos) : 0.0;

  // One-pixel features: how far the centre stands out from its neighbourhood's average.
  float average = (2.0 * (ln + ls + le + lw) + lne + lnw + lse + lsw) / 12.0;
  float stand_out = clamp(abs(average - lc) / range, 0.0, 1.0);
  stand_out = smoothstep(0.0, 1.0, stand_out);
  blend = max(blend, kSubpixel * stand_out * stand_out);

  frag_color = vec4(textureLod(u_image, uv + across * blend, 0.0).rgb, 1.0);
#endif
}
