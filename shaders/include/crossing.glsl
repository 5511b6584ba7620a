// One crossing of a transmissive surface: its transmittance per channel, s and p (the
// reflectance is 1 − T), under the surface's thin film in IRIDESCENCE variants (Rust:
// crates/reference/src/transmission.rs, crossing). Shared by the forward pass's
// screen-space transmission and the path tracer. Needs fresnel.glsl (and thin_film.glsl
// in IRIDESCENCE variants), as brdf.glsl includes them.
#ifndef COMBUSTION_CROSSING_GLSL
#define COMBUSTION_CROSSING_GLSL

struct Crossing {
    vec3 s;
    vec3 p;
};

// `film`: the film's weight, IOR and thickness in nm (weight 0: none).
Crossing surface_crossing(float cos_theta, float eta_from, float eta_to, vec3 film) {
    Crossing c;
#ifdef IRIDESCENCE
    film_crossing_transmittance(cos_theta, eta_from, eta_to, ThinFilm(film.x, film.y, film.z),
                                c.s, c.p);
#else
    vec2 t = fresnel_dielectric_transmittance(cos_theta, eta_from, eta_to);
    c.s = vec3(t.x);
    c.p = vec3(t.y);
#endif
    return c;
}

#endif
