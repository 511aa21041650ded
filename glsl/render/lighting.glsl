// One point light with inverse-square falloff, as in CS184: irradiance I / r^2.
#pragma once

#include "colour.glsl"

uniform vec3 u_light_position;   // world space, m
uniform vec3 u_light_intensity;  // radiant intensity per channel

const float kAmbient = 0.1;     // ambient coefficient ka, with ambient light 1
const float kSpecular = 0.5;    // specular coefficient ks
const float kShininess = 64.0;  // Blinn-Phong exponent p

vec3 lightDirection(vec3 position) {
  return normalize(u_light_position - position);
}

vec3 irradiance(vec3 position) {
  vec3 to_light = u_light_position - position;
  return u_light_intensity / max(dot(to_light, to_light), 1e-6);
}

// Blinn-Phong terms of one light, kept apart so the Phong program can show each alone.
struct PhongTerms {
  vec3 ambient;
  vec3 diffuse;
  vec3 specular;
};

// colour: the diffuse reflectance, linear.
PhongTerms blinnPhong(vec3 position, vec3 n, vec3 eye, vec3 colour) {
  vec3 l = lightDirection(position);
  vec3 v = normalize(eye - position);
  vec3 h = normalize(l + v);
  vec3 e = irradiance(position);
  float n_dot_l = max(dot(n, l), 0.0);
  PhongTerms t;
  t.ambient = kAmbient * colour;
  t.diffuse = colour * e * n_dot_l;
  // No highlight on the side facing away from the light.
  t.specular = n_dot_l > 0.0 ? kSpecular * e * pow(max(dot(n, h), 0.0), kShininess) : vec3(0.0);
  return t;
}
