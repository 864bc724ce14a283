// The rasterizer's GLSL. Conventions: world-space lighting; radiance out =
// emission + ambient * albedo + sum over lights of
//   (albedo / pi + specular * (s + 8) / (8 pi) * (n.h)^s) * E * max(n.l, 0) * visibility
// (Blinn-Phong with the (s + 8) / (8 pi) normalization of Akenine-Moller,
// Haines and Hoffman, Real-Time Rendering, 3rd ed., sec. 7.6), with E the light's irradiance (intensity / d^2, or the
// directional irradiance). Shadow maps store a linear depth metric in scene
// units (distance along a directional light, or to a spot or point light).
#include "shader_sources.hpp"

#include <string>

#define LOOM_SURFACE_BLOCK \
  "{ vec3 P; vec3 N; vec2 uv; vec3 dpdu; vec3 dpdv; vec3 color; }"

namespace loom::shading {

void bind_sampler_units(GlProgram& p) {
  p.set("u_base_map", static_cast<int>(unit_base));
  p.set("u_normal_map", static_cast<int>(unit_normal));
  p.set("u_displacement_map", static_cast<int>(unit_displacement));
  p.set("u_env_map", static_cast<int>(unit_environment));
  for (int i = 0; i < max_shadows; ++i) {
    p.set(("u_shadow_map[" + std::to_string(i) + "]").c_str(), static_cast<int>(unit_shadow + i));
    p.set(("u_shadow_cube[" + std::to_string(i) + "]").c_str(), static_cast<int>(unit_cube + i));
  }
}

namespace {

// Light kinds and shadow filters as the lighting GLSL knows them: each name is
// #defined to its position here, for every program (lighting_defines).
constexpr std::pair<Light::Kind, const char*> light_kinds[] = {{Light::Kind::point, "LIGHT_POINT"},
                                                               {Light::Kind::spot, "LIGHT_SPOT"},
                                                               {Light::Kind::directional, "LIGHT_DIRECTIONAL"}};
constexpr std::pair<ShadowFilter, const char*> shadow_filters[] = {{ShadowFilter::off, "FILTER_NONE"},
                                                                   {ShadowFilter::hard, "FILTER_HARD"},
                                                                   {ShadowFilter::pcf, "FILTER_PCF"},
                                                                   {ShadowFilter::pcss, "FILTER_PCSS"}};

template <class Enum, std::size_t N>
const char* glsl_name(const std::pair<Enum, const char*> (&table)[N], Enum value) {
  for (const auto& [e, name] : table)
    if (e == value) return name;
  return table[0].second;
}

template <class Enum, std::size_t N>
std::string glsl_codes(const std::pair<Enum, const char*> (&table)[N]) {
  std::string d;
  for (std::size_t i = 0; i < N; ++i) d += "#define " + std::string(table[i].second) + " " + std::to_string(i) + "\n";
  return d;
}

}  // namespace

std::string lighting_defines(const LightingVariant& v) {
  std::string d = "#define MAX_LIGHTS " + std::to_string(max_lights) + "\n#define MAX_SHADOWS " +
                  std::to_string(max_shadows) + "\n" + glsl_codes(light_kinds) + glsl_codes(shadow_filters);
  d += "#define SHADOW_FILTER " + std::string(glsl_name(shadow_filters, v.shadow_filter)) + "\n#define PCF_SIZE " +
       std::to_string(v.pcf_size) + "\n#define ENV_MAP " + std::to_string(v.environment_map ? 1 : 0) +
       "\n#define LIGHTS";
  for (std::size_t i = 0; i < v.lights.size(); ++i) {
    const auto [kind, slot] = v.lights[i];
    const std::string k = glsl_name(light_kinds, kind);
    d += slot >= 0 ? " SHADOWED(" + std::to_string(i) + ", " + k + ", " + std::to_string(slot) + ")"
                   : " LIT(" + std::to_string(i) + ", " + k + ")";
  }
  return d + "\n";
}

}  // namespace loom::shading

namespace loom::shading::glsl {

const char* const mesh_vertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec3 a_dpdu;
layout(location = 4) in vec3 a_dpdv;
layout(location = 5) in vec3 a_color;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_proj;
out Surface )" LOOM_SURFACE_BLOCK R"( v;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v.P = world.xyz;
  v.N = u_normal_matrix * a_normal;
  v.uv = a_uv;
  v.dpdu = mat3(u_model) * a_dpdu;
  v.dpdv = mat3(u_model) * a_dpdv;
  v.color = a_color;
  gl_Position = u_view_proj * world;
}
)";

const char* const mesh_tess_control = R"(#version 450 core
layout(vertices = 3) out;
in Surface )" LOOM_SURFACE_BLOCK R"( v[];
out Surface )" LOOM_SURFACE_BLOCK R"( t[];
uniform float u_tess_level;
void main() {
  t[gl_InvocationID].P = v[gl_InvocationID].P;
  t[gl_InvocationID].N = v[gl_InvocationID].N;
  t[gl_InvocationID].uv = v[gl_InvocationID].uv;
  t[gl_InvocationID].dpdu = v[gl_InvocationID].dpdu;
  t[gl_InvocationID].dpdv = v[gl_InvocationID].dpdv;
  t[gl_InvocationID].color = v[gl_InvocationID].color;
  if (gl_InvocationID == 0) {
    gl_TessLevelInner[0] = u_tess_level;
    gl_TessLevelOuter[0] = u_tess_level;
    gl_TessLevelOuter[1] = u_tess_level;
    gl_TessLevelOuter[2] = u_tess_level;
  }
}
)";

// Displacement: P' = P + h(uv) * scale * N along the interpolated original
// normal; the shading normal of P' is recomputed per fragment.
const char* const mesh_tess_eval = R"(#version 450 core
layout(triangles, equal_spacing, ccw) in;
in Surface )" LOOM_SURFACE_BLOCK R"( t[];
out Surface )" LOOM_SURFACE_BLOCK R"( v;
uniform sampler2D u_displacement_map;
uniform float u_displacement_scale;
uniform mat4 u_view_proj;
void main() {
  vec3 b = gl_TessCoord;
  v.P = b.x * t[0].P + b.y * t[1].P + b.z * t[2].P;
  v.N = b.x * t[0].N + b.y * t[1].N + b.z * t[2].N;
  v.uv = b.x * t[0].uv + b.y * t[1].uv + b.z * t[2].uv;
  v.dpdu = b.x * t[0].dpdu + b.y * t[1].dpdu + b.z * t[2].dpdu;
  v.dpdv = b.x * t[0].dpdv + b.y * t[1].dpdv + b.z * t[2].dpdv;
  v.color = b.x * t[0].color + b.y * t[1].color + b.z * t[2].color;
  float len = length(v.N);
  vec3 n = len > 0.0 ? v.N / len : vec3(0.0);
  float h = textureLod(u_displacement_map, vec2(v.uv.x, 1.0 - v.uv.y), 0.0).r;
  v.P += n * h * u_displacement_scale;
  gl_Position = u_view_proj * vec4(v.P, 1.0);
}
)";

namespace {
// The lighting code is compiled per feature set (lighting_defines): llvmpipe
// runs both sides of a branch under a mask, so code behind a uniform that is
// off still costs its full price per fragment. The defines it expects are
// lighting_defines' (LIGHTS: a list of LIT(i, kind) and SHADOWED(i, kind, slot)).
const char* const lighting = R"(
const float PI = 3.14159265358979;
uniform vec3 u_eye;
uniform vec3 u_ambient;
uniform vec3 u_light_position[MAX_LIGHTS];
uniform vec3 u_light_direction[MAX_LIGHTS];    // where the light shines
uniform vec3 u_light_radiance[MAX_LIGHTS];     // color * intensity
uniform float u_spot_cos_inner[MAX_LIGHTS];
uniform float u_spot_cos_outer[MAX_LIGHTS];
uniform float u_bias, u_slope_bias;            // in shadow-map texels
uniform float u_light_size;                    // pcss: emitter radius, or tan(angular radius)
uniform mat4 u_shadow_matrix[MAX_SHADOWS];     // world -> the map's window coordinates, [0,1] inside (2D maps)
uniform vec3 u_shadow_origin[MAX_SHADOWS];
uniform vec3 u_shadow_axis[MAX_SHADOWS];
uniform float u_shadow_texel[MAX_SHADOWS];     // texel size in scene units (at unit depth if perspective)
uniform int u_shadow_resolution[MAX_SHADOWS];
uniform vec2 u_shadow_depth_range[MAX_SHADOWS];  // stored -> metric: x + y * stored (ortho maps hold depth01)
uniform sampler2D u_shadow_map[MAX_SHADOWS];
uniform samplerCube u_shadow_cube[MAX_SHADOWS];

vec3 safe_normalize(vec3 v, vec3 fallback) {
  float l2 = dot(v, v);
  return l2 > 1e-38 ? v * inversesqrt(l2) : fallback;
}

#if SHADOW_FILTER != FILTER_NONE
// The stored depth `off` texels away from the receiver's lookup point.
float stored_depth(int s, bool cube, vec2 uv, vec3 dir, vec3 t, vec3 b, vec2 off) {
  if (cube) {
    float step = 2.0 / float(u_shadow_resolution[s]);
    return texture(u_shadow_cube[s], dir + (off.x * t + off.y * b) * step).r;
  }
  // texelFetch: no filtering or wrapping work for llvmpipe to do per tap.
  // Taps past the map's edge see nothing (lit), rather than the edge texel's
  // depth, which belongs to another surface point.
  int n = u_shadow_resolution[s];
  ivec2 texel = ivec2(floor(uv * float(n) + off));
  if (any(lessThan(texel, ivec2(0))) || any(greaterThanEqual(texel, ivec2(n)))) return 1e30;
  return u_shadow_depth_range[s].x + u_shadow_depth_range[s].y * texelFetch(u_shadow_map[s], texel, 0).r;
}

// Fraction of the light seen from P: shadow-map test with a constant plus
// slope-scaled bias (both in texels; the slope term grows with the filter
// radius, since the receiver's depth varies across the kernel), then hard, PCF
// (k x k texels) or PCSS (Fernando 2005: blocker search, penumbra
// w = light_size (d_receiver - d_blocker) / d_blocker, PCF of that width).
// s and kind are constants where it is called (one call per shadowed light).
float visibility(int s, int kind, vec3 P, vec3 N, vec3 L) {
  bool cube = kind == LIGHT_POINT;
  bool ortho = kind == LIGHT_DIRECTIONAL;
  vec3 v = P - u_shadow_origin[s];
  // Perspective maps (spot, point) store the distance to the light, so the
  // slope term, which follows the angle to the light, matches how the stored
  // depth varies across texels; orthographic maps store depth along the light.
  float d = ortho ? dot(v, u_shadow_axis[s]) : length(v);
  // An orthographic map's window depth is its stored depth; its w is 1.
  vec4 q = vec4(0.0, 0.0, 0.0, 1.0);
  if (!cube) {
    q = u_shadow_matrix[s] * vec4(P, 1.0);
    if (!ortho) {
      if (q.w <= 0.0) return 1.0;
      q.xy /= q.w;
    }
    if (any(lessThan(q.xy, vec2(0.0))) || any(greaterThan(q.xy, vec2(1.0)))) return 1.0;
  }
  vec2 uv = q.xy;
  vec3 dir = safe_normalize(v, vec3(0.0, 0.0, 1.0));
  vec3 t = vec3(1.0, 0.0, 0.0), b = vec3(0.0, 1.0, 0.0);
  if (cube) {
    t = safe_normalize(cross(dir, abs(dir.y) < 0.9 ? vec3(0, 1, 0) : vec3(1, 0, 0)), vec3(1, 0, 0));
    b = cross(dir, t);
  }
  float texel = u_shadow_texel[s] * (ortho ? 1.0 : d);
  float c = clamp(dot(N, L), 1e-3, 1.0);
  float tan_theta = min(sqrt(1.0 - c * c) / c, 10.0);
#if SHADOW_FILTER == FILTER_HARD
  // A plane tilted by theta changes depth by tan(theta) per texel: half a
  // texel for the lookup itself.
  float bias = texel * (u_bias + u_slope_bias * tan_theta * 0.5);
  return d - bias <= stored_depth(s, cube, uv, dir, t, b, vec2(0.0)) ? 1.0 : 0.0;
#else
#if SHADOW_FILTER == FILTER_PCF
  const int n = PCF_SIZE;
  float radius = 0.5 * float(n - 1);
  float step = 1.0;
#else
  // Blocker search over the penumbra a blocker halfway to the light would cast.
  float search = clamp(u_light_size * (ortho ? 0.5 * d : 1.0) / texel, 1.0, 24.0);
  float sum = 0.0, count = 0.0;
  float bias0 = texel * (u_bias + u_slope_bias * tan_theta * (0.5 + 1.415 * search));
  for (int y = -3; y <= 3; ++y)
    for (int x = -3; x <= 3; ++x) {
      float z = stored_depth(s, cube, uv, dir, t, b, vec2(x, y) * (search / 3.0));
      if (z < d - bias0) { sum += z; count += 1.0; }
    }
  if (count == 0.0) return 1.0;
  float blocker = sum / count;
  float penumbra = ortho ? u_light_size * (d - blocker)
                         : u_light_size * (d - blocker) / max(blocker, 1e-6);
  float radius = clamp(penumbra / texel, 0.5, 32.0);
  const int n = 8;
  float step = 2.0 * radius / float(n - 1);
#endif
  // The farthest kernel sample is sqrt 2 radius away (diagonally), plus the
  // half texel of the lookup itself.
  float bias = texel * (u_bias + u_slope_bias * tan_theta * (0.5 + 1.415 * radius));
#if SHADOW_FILTER == FILTER_PCF
  if (!cube) {
    // The same n x n texels as one texelFetch each, 2 x 2 per textureGather
    // (a quarter of the lookups). Texels past the edge read the border (1e30,
    // or depth 1 = the far plane for ortho maps): nothing there, lit. Gather order: (x0,y1) (x1,y1) (x1,y0) (x0,y0).
    // The receiver's depth on the map's stored scale (stored_depth's range
    // inverted; an orthographic map's window depth is already on it),
    // compared with the stored depths as they are.
    float res = float(u_shadow_resolution[s]), texel_uv = 1.0 / res;
    vec2 range = u_shadow_depth_range[s];
    float receiver = ortho ? q.z - bias / range.y : (d - bias - range.x) / range.y;
    vec2 corner = (floor(uv * res - 0.5 * float(n - 1)) + 1.0) * texel_uv;
    float lit = 0.0;
    for (int gy = 0; gy < n; gy += 2)
      for (int gx = 0; gx < n; gx += 2) {
        vec4 z = textureGather(u_shadow_map[s], corner + vec2(gx, gy) * texel_uv, 0);
        float wx = gx + 1 < n ? 1.0 : 0.0, wy = gy + 1 < n ? 1.0 : 0.0;
        lit += dot(vec4(greaterThanEqual(z, vec4(receiver))), vec4(wy, wx * wy, wx, 1.0));
      }
    return lit / float(n * n);
  }
#endif
  float h = 0.5 * float(n - 1) * step;
  if (n >= 4) {
    // Early out: the kernel's four corners and center agree (a fully lit or
    // fully shadowed neighbourhood, most of the image): skip the other taps.
    float e = 0.0;
    e += d - bias <= stored_depth(s, cube, uv, dir, t, b, vec2(-h, -h)) ? 1.0 : 0.0;
    e += d - bias <= stored_depth(s, cube, uv, dir, t, b, vec2(h, -h)) ? 1.0 : 0.0;
    e += d - bias <= stored_depth(s, cube, uv, dir, t, b, vec2(-h, h)) ? 1.0 : 0.0;
    e += d - bias <= stored_depth(s, cube, uv, dir, t, b, vec2(h, h)) ? 1.0 : 0.0;
    e += d - bias <= stored_depth(s, cube, uv, dir, t, b, vec2(0.0)) ? 1.0 : 0.0;
    if (e == 0.0 || e == 5.0) return e / 5.0;
  }
  float lit = 0.0;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      lit += d - bias <= stored_depth(s, cube, uv, dir, t, b, (vec2(x, y) - 0.5 * float(n - 1)) * step) ? 1.0 : 0.0;
  return lit / float(n * n);
#endif
}
#endif

// Direction to light i and its irradiance E at P (kind constant at the call).
vec3 incidence(int i, int kind, vec3 P, out vec3 E) {
  E = u_light_radiance[i];
  if (kind == LIGHT_DIRECTIONAL) return -u_light_direction[i];
  vec3 to_light = u_light_position[i] - P;
  float d2 = max(dot(to_light, to_light), 1e-12);
  vec3 L = to_light * inversesqrt(d2);
  E /= d2;
  if (kind == LIGHT_SPOT) E *= smoothstep(u_spot_cos_outer[i], u_spot_cos_inner[i], dot(-L, u_light_direction[i]));
  return L;
}

vec3 blinn_phong(vec3 N, vec3 L, vec3 V, vec3 albedo, float specular, float shininess) {
  float cos_theta = dot(N, L);
  if (cos_theta <= 0.0) return vec3(0.0);
  vec3 H = safe_normalize(L + V, N);
  float spec = specular * (shininess + 8.0) / (8.0 * PI) * pow(max(dot(N, H), 0.0), shininess);
  return (albedo / PI + vec3(spec)) * cos_theta;
}

#if ENV_MAP
// A lat-long environment: diffuse light from its 9 SH irradiance
// coefficients (R&H 2001 eq. 7, intensity included), glossy reflection from
// its mip chain at the level whose box filter is as wide as the lobe.
uniform vec3 u_env_sh[9];
uniform sampler2D u_env_map;
uniform float u_env_rotation, u_env_intensity, u_env_height, u_env_max_level;
uniform vec3 u_env_reflectance;               // per material: 0 for diffuse surfaces

vec3 env_irradiance(vec3 n) {
  return u_env_sh[0] * 0.282095
       + u_env_sh[1] * (0.488603 * n.y) + u_env_sh[2] * (0.488603 * n.z) + u_env_sh[3] * (0.488603 * n.x)
       + u_env_sh[4] * (1.092548 * n.x * n.y) + u_env_sh[5] * (1.092548 * n.y * n.z)
       + u_env_sh[6] * (0.315392 * (3.0 * n.z * n.z - 1.0)) + u_env_sh[7] * (1.092548 * n.x * n.z)
       + u_env_sh[8] * (0.546274 * (n.x * n.x - n.y * n.y));
}

// loom::latlong_uv: u from atan2(x, -z) less the rotation, v = theta / pi
// (the map's top row is uploaded first: t = v).
vec3 env_radiance(vec3 d, float level) {
  float u = (atan(d.x, -d.z) - u_env_rotation) / (2.0 * PI) + 0.5;
  float v = acos(clamp(d.y, -1.0, 1.0)) / PI;
  return u_env_intensity * textureLod(u_env_map, vec2(u, v), level).rgb;
}

// Blinn-Phong with exponent s is about a Phong lobe cos^(s/4) about the
// mirror direction, a Gaussian of sigma = 2 / sqrt(s) radians; a box of width
// w has sigma w / sqrt(12), and level k's texels are 2^k pi / H wide.
vec3 env_reflection(vec3 N, vec3 V, float shininess) {
  vec3 R = reflect(-V, N);
  float sigma = 2.0 / sqrt(max(shininess, 1.0));
  float level = clamp(log2(sigma * sqrt(12.0) * u_env_height / PI), 0.0, u_env_max_level);
  return u_env_reflectance * env_radiance(R, level);
}
#endif

#define LIT(i, kind) { vec3 E; vec3 L = incidence(i, kind, P, E); \
  radiance += blinn_phong(N, L, V, albedo, specular, shininess) * E; }
#define SHADOWED(i, kind, slot) { vec3 E; vec3 L = incidence(i, kind, P, E); \
  float vis = visibility(slot, kind, P, G, L); if (slot == 0) shadow_out = vis; \
  radiance += blinn_phong(N, L, V, albedo, specular, shininess) * E * vis; }

// Outgoing radiance at P (shading normal N, geometric normal G: the shadow
// bias follows the surface, not its normal map) toward the eye; shadow_out is
// the visibility of the first shadowed light (for the shadow image).
vec3 shade(vec3 P, vec3 N, vec3 G, vec3 albedo, float specular, float shininess, out float shadow_out) {
  vec3 V = safe_normalize(u_eye - P, N);
#if ENV_MAP
  vec3 radiance = albedo / PI * env_irradiance(N) + env_reflection(N, V, shininess);
#else
  vec3 radiance = albedo * u_ambient;
#endif
  shadow_out = 1.0;
  LIGHTS
  return radiance;
}
)";
}  // namespace

std::string mesh_fragment(const std::string& defines) {
  return "#version 450 core\n" + defines + lighting + R"(
in Surface )" LOOM_SURFACE_BLOCK R"( v;
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_position;
layout(location = 3) out vec4 o_shadow;
uniform mat4 u_view;
uniform vec3 u_base_color;
uniform vec3 u_emission;
uniform float u_specular;
uniform float u_shininess;
uniform float u_displacement_scale;
uniform sampler2D u_base_map;
uniform sampler2D u_normal_map;
uniform sampler2D u_displacement_map;

float height(vec2 uv) { return texture(u_displacement_map, vec2(uv.x, 1.0 - uv.y)).r; }

void main() {
  vec3 N = safe_normalize(v.N, vec3(0.0, 0.0, 1.0));
  if (!gl_FrontFacing) N = -N;
  vec2 tex_uv = vec2(v.uv.x, 1.0 - v.uv.y);
#if HAS_DISPLACEMENT
  // The displaced surface P + s h N: dP'/du = dP/du + s h_u N (the change
  // of N itself neglected), n' = dP'/du x dP'/dv.
  vec2 texel = 1.0 / vec2(textureSize(u_displacement_map, 0));
  float hu = (height(v.uv + vec2(texel.x, 0)) - height(v.uv - vec2(texel.x, 0))) / (2.0 * texel.x);
  float hv = (height(v.uv + vec2(0, texel.y)) - height(v.uv - vec2(0, texel.y))) / (2.0 * texel.y);
  vec3 du = v.dpdu + u_displacement_scale * hu * N;
  vec3 dv = v.dpdv + u_displacement_scale * hv * N;
  vec3 n = safe_normalize(cross(du, dv), N);
  N = dot(n, N) < 0.0 ? -n : n;
#endif
  vec3 G = N;
#if HAS_NORMAL_MAP
  // Tangent frame by Gram-Schmidt: T = dP/du minus its part along N; B
  // completes it with the handedness of the UV map.
  vec3 T = safe_normalize(v.dpdu - N * dot(N, v.dpdu), vec3(0.0));
  if (T != vec3(0.0)) {
    vec3 B = cross(N, T);
    if (dot(B, v.dpdv) < 0.0) B = -B;
    vec3 m = texture(u_normal_map, tex_uv).xyz * 2.0 - 1.0;
    N = safe_normalize(T * m.x + B * m.y + N * m.z, N);
  }
#endif
  vec3 albedo = u_base_color;
#if HAS_VERTEX_COLOR
  albedo *= v.color;  // read only where the mesh has colours: each varying costs llvmpipe's triangle setup
#endif
#if HAS_BASE_MAP
  albedo *= texture(u_base_map, tex_uv).rgb;
#endif
  float shadow;
  vec3 c = u_emission + shade(v.P, N, G, albedo, u_specular, u_shininess, shadow);
  o_color = vec4(max(c, vec3(0.0)), 1.0);
  o_normal = vec4(N, 1.0);
  o_position = vec4(v.P, -(u_view * vec4(v.P, 1.0)).z);
  o_shadow = vec4(shadow, 0.0, 0.0, 1.0);
}
)";
}

const char* const empty_fragment = R"(#version 450 core
void main() {}
)";

const char* const depth_fragment = R"(#version 450 core
in Surface )" LOOM_SURFACE_BLOCK R"( v;
layout(location = 0) out float o_depth;
uniform vec3 u_depth_origin;
uniform vec3 u_depth_axis;
uniform bool u_depth_radial;
void main() {
  vec3 d = v.P - u_depth_origin;
  o_depth = u_depth_radial ? length(d) : dot(d, u_depth_axis);
}
)";

const char* const sphere_vertex = R"(#version 450 core
layout(location = 0) in vec3 a_center;
layout(location = 1) in float a_radius;
layout(location = 2) in vec3 a_color;
uniform mat4 u_model;
uniform float u_radius_scale;
out Sphere { vec3 center; float radius; vec3 color; } s;
void main() {
  s.center = (u_model * vec4(a_center, 1.0)).xyz;
  s.radius = a_radius * u_radius_scale;
  s.color = a_color;
}
)";

// A quad facing the eye that covers the sphere's silhouette cone exactly:
// at distance d - r along the axis eye -> center, half-size
// (d - r) r / sqrt(d^2 - r^2); orthographic views use the view axis.
const char* const sphere_geometry = R"(#version 450 core
layout(points) in;
layout(triangle_strip, max_vertices = 4) out;
in Sphere { vec3 center; float radius; vec3 color; } s[];
out Impostor { vec3 center; float radius; vec3 color; } o;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform bool u_ortho;
void main() {
  vec3 c = (u_view * vec4(s[0].center, 1.0)).xyz;
  float r = s[0].radius;
  if (r <= 0.0) return;
  vec3 axis;
  vec3 base;
  float half_size;
  if (u_ortho) {
    axis = vec3(0.0, 0.0, -1.0);
    base = c - axis * r;
    half_size = r;
  } else {
    float d = length(c);
    if (d <= r * 1.0001) return;
    axis = c / d;
    base = axis * (d - r);
    half_size = (d - r) * r / sqrt(d * d - r * r) * 1.01;
  }
  vec3 x = normalize(cross(axis, abs(axis.y) < 0.9 ? vec3(0, 1, 0) : vec3(1, 0, 0)));
  vec3 y = cross(x, axis);
  for (int k = 0; k < 4; ++k) {
    vec2 corner = vec2(k & 1, k >> 1) * 2.0 - 1.0;
    vec3 p = base + (corner.x * x + corner.y * y) * half_size;
    o.center = s[0].center;
    o.radius = r;
    o.color = s[0].color;
    gl_Position = u_proj * vec4(p, 1.0);
    EmitVertex();
  }
  EndPrimitive();
}
)";

std::string sphere_fragment(const std::string& defines) {
  return "#version 450 core\n" + defines + lighting + R"(
in Impostor { vec3 center; float radius; vec3 color; } s;
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_position;
layout(location = 3) out vec4 o_shadow;
uniform mat4 u_view;
uniform mat4 u_proj;
uniform mat4 u_inverse_view_proj;
uniform vec2 u_viewport;
uniform float u_specular;
uniform float u_shininess;
uniform vec3 u_depth_origin;
uniform vec3 u_depth_axis;
uniform bool u_depth_radial;
void main() {
  // The pixel's ray (world space), from the near to the far plane.
  vec2 ndc = gl_FragCoord.xy / u_viewport * 2.0 - 1.0;
  vec4 a = u_inverse_view_proj * vec4(ndc, -1.0, 1.0);
  vec4 b = u_inverse_view_proj * vec4(ndc, 1.0, 1.0);
  vec3 origin = a.xyz / a.w;
  vec3 dir = normalize(b.xyz / b.w - origin);
  vec3 oc = origin - s.center;
  float half_b = dot(oc, dir);
  float disc = half_b * half_b - (dot(oc, oc) - s.radius * s.radius);
  if (disc < 0.0) discard;
  float t = -half_b - sqrt(disc);
  vec3 P = origin + t * dir;
  vec3 N = (P - s.center) / s.radius;
  vec4 clip = u_proj * u_view * vec4(P, 1.0);
  gl_FragDepth = clamp(0.5 * clip.z / clip.w + 0.5, 0.0, 1.0);
#if DEPTH_PASS
  vec3 d = P - u_depth_origin;
  o_color = vec4(u_depth_radial ? length(d) : dot(d, u_depth_axis));
#else
  float shadow;
  o_color = vec4(max(shade(P, N, N, s.color, u_specular, u_shininess, shadow), vec3(0.0)), 1.0);
  o_normal = vec4(N, 1.0);
  o_position = vec4(P, -(u_view * vec4(P, 1.0)).z);
  o_shadow = vec4(shadow, 0.0, 0.0, 1.0);
#endif
}
)";
}



const char* const background_vertex = R"(#version 450 core
out vec2 v_ndc;
void main() {
  // One triangle covering the viewport, at the far plane.
  vec2 p = vec2((gl_VertexID & 1) * 4 - 1, (gl_VertexID & 2) * 2 - 1);
  v_ndc = p;
  gl_Position = vec4(p, 1.0, 1.0);
}
)";

std::string background_fragment() {
  LightingVariant v;
  v.environment_map = true;
  return "#version 450 core\n" + lighting_defines(v) + lighting + R"(
in vec2 v_ndc;
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_position;
layout(location = 3) out vec4 o_shadow;
uniform mat4 u_inverse_view_proj;
uniform float u_far;
void main() {
  vec4 a = u_inverse_view_proj * vec4(v_ndc, -1.0, 1.0);
  vec4 b = u_inverse_view_proj * vec4(v_ndc, 1.0, 1.0);
  vec3 d = normalize(b.xyz / b.w - a.xyz / a.w);
  o_color = vec4(env_radiance(d, 0.0), 0.0);  // alpha: coverage, none
  o_normal = vec4(0.0);
  o_position = vec4(0.0, 0.0, 0.0, u_far);
  o_shadow = vec4(1.0, 0.0, 0.0, 0.0);
}
)";
}

const char* const line_vertex = R"(#version 450 core
layout(location = 0) in vec3 a_position;
layout(location = 5) in vec3 a_color;
uniform mat4 u_model;
uniform mat4 u_view_proj;
out vec3 v_color;
out vec3 v_world;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_color = a_color;
  gl_Position = u_view_proj * world;
}
)";

const char* const line_fragment = R"(#version 450 core
in vec3 v_color;
in vec3 v_world;
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_position;
layout(location = 3) out vec4 o_shadow;
uniform mat4 u_view;
uniform bool u_uniform_color;
uniform vec3 u_color;
void main() {
  o_color = vec4(u_uniform_color ? u_color : v_color, 1.0);
  o_normal = vec4(0.0, 0.0, 0.0, 1.0);
  o_position = vec4(v_world, -(u_view * vec4(v_world, 1.0)).z);
  o_shadow = vec4(1.0);
}
)";

}  // namespace loom::shading::glsl
