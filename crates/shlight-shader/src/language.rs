//! How each target language spells what the lookups are made of: types,
//! locals, casts, constants, arrays, function signatures, loops and
//! selections.
//!
//! | | WGSL | GLSL | HLSL | C |
//! |---|---|---|---|---|
//! | float, vector | `f32`, `vec3<f32>` | `float`, `vec3` | `float`, `float3` | `double`, `double[3]` |
//! | constant local | `let x = e;` | `float x = e;` | `float x = e;` | `const double x = e;` |
//! | variable | `var x = e;` / `var x: f32 = e;` | `float x = e;` | `float x = e;` | `double x = e;` |
//! | cast | `f32(e)` | `float(e)` | `float(e)` | `(double)(e)` |
//! | module constant | `const X: i32 = 1;` | `const int X = 1;` | `static const int X = 1;` | `#define X 1` |
//! | array constant | `var<private> A: array<f32, 2> = array<f32, 2>(..);` | `const float A[2] = float[2](..);` | `static const float A[2] = {..};` | `static const double a[2] = {..};` |
//! | function | `fn f(n: vec3<f32>) -> vec3<f32>` | `vec3 f(vec3 n)` | `float3 f(float3 n)` | `static inline void f(const double n[3], double out[3])` |
//! | selection | `select(f, t, c)` | `c ? t : f` | `c ? t : f` | `c ? t : f` |
//!
//! C has no vector type: a vector parameter is an array, a vector result
//! an `out` array the function writes, and the lookups spell C's vector
//! arithmetic channel by channel. Its floats are doubles (the snippets'
//! coefficients keep their f64 values); the shading languages' are 32-bit.

/// A language shlight writes lookups in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Language {
    /// WGSL (WebGPU, wgpu, Bevy; shlight's own renderer).
    Wgsl,
    /// GLSL 3.30 / GLSL ES 3.00 and later.
    Glsl,
    /// HLSL (Direct3D, Unity, Unreal).
    Hlsl,
    /// C99, in double precision.
    C,
}

/// The shading languages that read textures: what the volume lookup
/// ([`crate::volume`]) and the visibility weights ([`crate::visibility`])
/// are written in (HLSL and C are not).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ShaderLanguage {
    /// WGSL (WebGPU, Bevy, wgpu): the textures are the function's
    /// parameters.
    Wgsl,
    /// GLSL (`#version 300 es` / WebGL2, and desktop 330 and later): the
    /// textures are `sampler3D` uniforms, or whatever the three fetch
    /// macros are defined to first.
    Glsl,
}

impl From<ShaderLanguage> for Language {
    fn from(lang: ShaderLanguage) -> Self {
        match lang {
            ShaderLanguage::Wgsl => Language::Wgsl,
            ShaderLanguage::Glsl => Language::Glsl,
        }
    }
}

/// A value's type in the lookups.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Type {
    /// A float (`f32`; C's `double`).
    Float,
    /// Two floats.
    Vec2,
    /// Three floats.
    Vec3,
    /// Four floats.
    Vec4,
    /// A signed 32-bit integer.
    Int,
    /// Two signed integers.
    IVec2,
    /// Three signed integers.
    IVec3,
    /// An unsigned 32-bit integer.
    Uint,
    /// A boolean.
    Bool,
    /// Three booleans.
    BVec3,
    /// A 3D float texture read with integer loads (a WGSL parameter).
    Texture3d,
}

impl Language {
    /// The type's name (C: the element type of an array for vectors).
    #[must_use]
    pub fn ty(self, t: Type) -> &'static str {
        use Type::*;
        match self {
            Language::Wgsl => match t {
                Float => "f32",
                Vec2 => "vec2<f32>",
                Vec3 => "vec3<f32>",
                Vec4 => "vec4<f32>",
                Int => "i32",
                IVec2 => "vec2<i32>",
                IVec3 => "vec3<i32>",
                Uint => "u32",
                Bool => "bool",
                BVec3 => "vec3<bool>",
                Texture3d => "texture_3d<f32>",
            },
            Language::Glsl => match t {
                Float => "float",
                Vec2 => "vec2",
                Vec3 => "vec3",
                Vec4 => "vec4",
                Int => "int",
                IVec2 => "ivec2",
                IVec3 => "ivec3",
                Uint => "uint",
                Bool => "bool",
                BVec3 => "bvec3",
                Texture3d => "sampler3D",
            },
            Language::Hlsl => match t {
                Float => "float",
                Vec2 => "float2",
                Vec3 => "float3",
                Vec4 => "float4",
                Int => "int",
                IVec2 => "int2",
                IVec3 => "int3",
                Uint => "uint",
                Bool => "bool",
                BVec3 => "bool3",
                Texture3d => "Texture3D<float4>",
            },
            Language::C => match t {
                Float | Vec2 | Vec3 | Vec4 => "double",
                Int | IVec2 | IVec3 | Bool | BVec3 => "int",
                Uint => "unsigned",
                // C reads a texture's floats through a pointer.
                Texture3d => "const float *",
            },
        }
    }

    /// Whether this is C (no vectors, double precision).
    #[must_use]
    pub fn is_c(self) -> bool {
        self == Language::C
    }

    /// A local that is not assigned again: `let x = e;` (WGSL),
    /// `float x = e;` (GLSL, HLSL), `const double x = e;` (C).
    #[must_use]
    pub fn let_(self, t: Type, name: &str, value: &str) -> String {
        match self {
            Language::Wgsl => format!("let {name} = {value};"),
            Language::C => format!("const {} {name} = {value};", self.ty(t)),
            _ => format!("{} {name} = {value};", self.ty(t)),
        }
    }

    /// A variable, its type left to WGSL to infer: `var x = e;`,
    /// `float x = e;`.
    #[must_use]
    pub fn var(self, t: Type, name: &str, value: &str) -> String {
        match self {
            Language::Wgsl => format!("var {name} = {value};"),
            _ => format!("{} {name} = {value};", self.ty(t)),
        }
    }

    /// A variable with its type written in WGSL too: `var x: f32 = e;`.
    #[must_use]
    pub fn var_typed(self, t: Type, name: &str, value: &str) -> String {
        match self {
            Language::Wgsl => format!("var {name}: {} = {value};", self.ty(t)),
            _ => self.var(t, name, value),
        }
    }

    /// `value` converted to `t`: `f32(e)`, `float(e)`, `(double)(e)`.
    #[must_use]
    pub fn cast(self, t: Type, value: &str) -> String {
        match self {
            Language::C => format!("({})({value})", self.ty(t)),
            _ => format!("{}({value})", self.ty(t)),
        }
    }

    /// A vector of `args`: `vec3<f32>(..)`, `vec3(..)`, `float3(..)`, C's
    /// initialiser `{..}`.
    #[must_use]
    pub fn vector(self, t: Type, args: &str) -> String {
        match self {
            Language::C => format!("{{{args}}}"),
            _ => format!("{}({args})", self.ty(t)),
        }
    }

    /// A module-scope constant: `const X: T = e;`, `const T X = e;`,
    /// `static const T X = e;`; C: an integer is `#define X e`, a vector
    /// `static const double x[3] = {..};` (lower case, as C's arrays are).
    #[must_use]
    pub fn constant(self, t: Type, name: &str, value: &str) -> String {
        match self {
            Language::Wgsl => format!("const {name}: {} = {value};", self.ty(t)),
            Language::Glsl => format!("const {} {name} = {value};", self.ty(t)),
            Language::Hlsl => format!("static const {} {name} = {value};", self.ty(t)),
            Language::C => match t {
                Type::Int | Type::Uint => format!("#define {name} {value}"),
                _ => format!(
                    "static const {} {}{} = {value};",
                    self.ty(t),
                    name.to_ascii_lowercase(),
                    c_dims(t)
                ),
            },
        }
    }

    /// The opening of a module-scope array constant of `n` elements of
    /// type `t` whose elements follow: `var<private> A: array<T, n> =
    /// array<T, n>(`, `const T A[n] = T[n](`, `static const T A[n] = {`,
    /// `static const double a[n][3] = {` (C's name lower case).
    ///
    /// WGSL's are `var<private>` so that they can be indexed by loop
    /// variables (a `const` array may only be indexed by constants in some
    /// implementations).
    #[must_use]
    pub fn array_open(self, t: Type, name: &str, n: &str) -> String {
        let ty = self.ty(t);
        match self {
            Language::Wgsl => {
                format!("var<private> {name}: array<{ty}, {n}> = array<{ty}, {n}>(")
            }
            Language::Glsl => format!("const {ty} {name}[{n}] = {ty}[{n}]("),
            Language::Hlsl => format!("static const {ty} {name}[{n}] = {{"),
            Language::C => format!(
                "static const {ty} {}[{n}]{} = {{",
                name.to_ascii_lowercase(),
                c_dims(t)
            ),
        }
    }

    /// What closes [`Language::array_open`]: `);` or `};`.
    #[must_use]
    pub fn array_close(self) -> &'static str {
        match self {
            Language::Wgsl | Language::Glsl => ");",
            Language::Hlsl | Language::C => "};",
        }
    }

    /// A module-scope array of `n` elements that the code writes:
    /// `var<private> a: array<T, n>;`, `T a[n];`, `static T a[n];`.
    #[must_use]
    pub fn private_array(self, t: Type, name: &str, n: usize) -> String {
        let ty = self.ty(t);
        match self {
            Language::Wgsl => format!("var<private> {name}: array<{ty}, {n}>;"),
            Language::Glsl => format!("{ty} {name}[{n}];"),
            Language::Hlsl => format!("static {ty} {name}[{n}];"),
            Language::C => format!("static {ty} {name}[{n}]{};", c_dims(t)),
        }
    }

    /// A function's signature (without the brace): `fn f(a: A) -> R`,
    /// `R f(A a)`; C's `static inline R f(..)`, where a vector parameter
    /// is `const double a[3]` and a vector result `void` with a last
    /// parameter `double out[3]`. `None`: no result.
    #[must_use]
    pub fn signature(self, result: Option<Type>, name: &str, params: &[(Type, &str)]) -> String {
        match self {
            Language::Wgsl => {
                let list: Vec<String> = params
                    .iter()
                    .map(|(t, p)| format!("{p}: {}", self.ty(*t)))
                    .collect();
                let ret = result.map_or(String::new(), |t| format!(" -> {}", self.ty(t)));
                format!("fn {name}({}){ret}", list.join(", "))
            }
            Language::Glsl | Language::Hlsl => {
                let list: Vec<String> = params
                    .iter()
                    .map(|(t, p)| format!("{} {p}", self.ty(*t)))
                    .collect();
                let ret = result.map_or("void", |t| self.ty(t));
                format!("{ret} {name}({})", list.join(", "))
            }
            Language::C => {
                let mut list: Vec<String> = params
                    .iter()
                    .map(|(t, p)| match t {
                        Type::Float | Type::Int | Type::Uint | Type::Bool => {
                            format!("{} {p}", self.ty(*t))
                        }
                        _ => format!("const {} {p}{}", self.ty(*t), c_dims(*t)),
                    })
                    .collect();
                let ret = match result {
                    Some(t @ (Type::Float | Type::Int | Type::Uint | Type::Bool)) => self.ty(t),
                    Some(t) => {
                        list.push(format!("{} out{}", self.ty(t), c_dims(t)));
                        "void"
                    }
                    None => "void",
                };
                format!("static inline {ret} {name}({})", list.join(", "))
            }
        }
    }

    /// `if_true` where `condition` holds, else `if_false`: WGSL's
    /// `select(f, t, c)`, the others' `c ? t : f`.
    #[must_use]
    pub fn select(self, if_false: &str, if_true: &str, condition: &str) -> String {
        match self {
            Language::Wgsl => format!("select({if_false}, {if_true}, {condition})"),
            _ => format!("{condition} ? {if_true} : {if_false}"),
        }
    }

    /// The head of a counting loop, `for (var i = 0; i < n; i++) {`
    /// (`typed`: `var i: i32 = 0`), `for (int i = 0; i < n; i++) {`.
    #[must_use]
    pub fn for_open(self, var: &str, from: &str, condition: &str, typed: bool) -> String {
        let init = match self {
            Language::Wgsl if typed => format!("var {var}: i32 = {from}"),
            Language::Wgsl => format!("var {var} = {from}"),
            _ => format!("int {var} = {from}"),
        };
        format!("for ({init}; {condition}; {var}++) {{")
    }

    /// `max(a, b)` of floats (C: `fmax`).
    #[must_use]
    pub fn max(self, a: &str, b: &str) -> String {
        match self {
            Language::C => format!("fmax({a}, {b})"),
            _ => format!("max({a}, {b})"),
        }
    }

    /// `min(a, b)` of floats (C: `fmin`).
    #[must_use]
    pub fn min(self, a: &str, b: &str) -> String {
        match self {
            Language::C => format!("fmin({a}, {b})"),
            _ => format!("min({a}, {b})"),
        }
    }

    /// `clamp(v, lo, hi)` of floats (C: `fmin(fmax(v, lo), hi)`).
    #[must_use]
    pub fn clamp(self, v: &str, lo: &str, hi: &str) -> String {
        match self {
            Language::C => self.min(&self.max(v, lo), hi),
            _ => format!("clamp({v}, {lo}, {hi})"),
        }
    }

    /// A vector of `t` chosen lane by lane: lane `c` is `if_true`'s where
    /// `condition`'s holds, else `if_false`'s. WGSL's `select` of whole
    /// vectors; the others' constructor of one conditional per lane.
    pub(crate) fn select_lanes(
        self,
        t: Type,
        if_false: Lanes<'_>,
        if_true: Lanes<'_>,
        condition: Lanes<'_>,
    ) -> String {
        match self {
            Language::Wgsl => format!(
                "select({}, {}, {})",
                if_false.whole(self, t),
                if_true.whole(self, t),
                condition.whole(self, t)
            ),
            _ => {
                let lanes: Vec<String> = lanes(t)
                    .iter()
                    .map(|c| {
                        format!(
                            "{} ? {} : {}",
                            condition.lane(c),
                            if_true.lane(c),
                            if_false.lane(c)
                        )
                    })
                    .collect();
                self.vector(t, &lanes.join(", "))
            }
        }
    }

    /// The vector `if_true` where the scalar `condition` holds, else
    /// `if_false`: WGSL's `select(f, t, vec2<bool>(c))`, the others' `c ?
    /// t : f`.
    pub(crate) fn select_all(
        self,
        t: Type,
        if_false: &str,
        if_true: &str,
        condition: &str,
    ) -> String {
        match self {
            Language::Wgsl => format!(
                "select({if_false}, {if_true}, vec{}<bool>({condition}))",
                lanes(t).len()
            ),
            _ => self.select(if_false, if_true, condition),
        }
    }

    /// The language's boolean literal (C: `1` / `0`).
    #[must_use]
    pub fn boolean(self, v: bool) -> &'static str {
        match (self, v) {
            (Language::C, true) => "1",
            (Language::C, false) => "0",
            (_, true) => "true",
            (_, false) => "false",
        }
    }
}

/// The lanes of a vector type.
fn lanes(t: Type) -> &'static [&'static str] {
    match t {
        Type::Vec2 | Type::IVec2 => &["x", "y"],
        Type::Vec4 => &["x", "y", "z", "w"],
        _ => &["x", "y", "z"],
    }
}

/// An operand of [`Language::select_lanes`], written whole (WGSL) or lane
/// by lane.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Lanes<'a> {
    /// A vector by name: `v`, lane `v.x`.
    Name(&'a str),
    /// A scalar in every lane: `vec2<f32>(s)`, lane `s`.
    Splat(&'a str),
    /// One minus a vector: `vec3<f32>(1.0) - v`, lane `1.0 - v.x`.
    OneMinus(&'a str),
    /// A vector compared with a scalar: `v >= vec2<f32>(s)`, lane
    /// `v.x >= s`.
    Compare(&'a str, &'a str, &'a str),
}

impl Lanes<'_> {
    fn whole(self, lang: Language, t: Type) -> String {
        match self {
            Lanes::Name(v) => v.to_string(),
            Lanes::Splat(s) => lang.vector(t, s),
            Lanes::OneMinus(v) => format!("{} - {v}", lang.vector(t, "1.0")),
            Lanes::Compare(v, op, s) => format!("{v} {op} {}", lang.vector(t, s)),
        }
    }

    fn lane(self, c: &str) -> String {
        match self {
            Lanes::Name(v) => format!("{v}.{c}"),
            Lanes::Splat(s) => s.to_string(),
            Lanes::OneMinus(v) => format!("1.0 - {v}.{c}"),
            Lanes::Compare(v, op, s) => format!("{v}.{c} {op} {s}"),
        }
    }
}

/// C's array dimensions of a vector type (`[3]`), nothing for a scalar.
fn c_dims(t: Type) -> &'static str {
    match t {
        Type::Vec2 | Type::IVec2 => "[2]",
        Type::Vec3 | Type::IVec3 | Type::BVec3 => "[3]",
        Type::Vec4 => "[4]",
        _ => "",
    }
}

/// Lines of code at a nesting depth of four spaces a level: what the
/// lookups write their statements into.
#[derive(Clone, Debug, Default)]
pub struct Code {
    text: String,
    depth: usize,
}

impl Code {
    /// Empty, at depth 0.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Empty, at `depth`.
    #[must_use]
    pub fn at(depth: usize) -> Self {
        Self {
            text: String::new(),
            depth,
        }
    }

    /// One line at the current depth (an empty line has no indentation).
    pub fn line(&mut self, line: impl AsRef<str>) {
        let line = line.as_ref();
        if !line.is_empty() {
            for _ in 0..self.depth {
                self.text.push_str("    ");
            }
            self.text.push_str(line);
        }
        self.text.push('\n');
    }

    /// Each line of `lines` at the current depth.
    pub fn lines<S: AsRef<str>>(&mut self, lines: impl IntoIterator<Item = S>) {
        for line in lines {
            self.line(line);
        }
    }

    /// A line that opens a block (`... {`): what follows is one level deeper.
    pub fn open(&mut self, line: impl AsRef<str>) {
        self.line(line);
        self.depth += 1;
    }

    /// A line one level up that closes a block (`}`).
    pub fn close(&mut self, line: impl AsRef<str>) {
        self.depth = self.depth.saturating_sub(1);
        self.line(line);
    }

    /// A line one level up that closes a block and opens the next
    /// (`} else {`).
    pub fn reopen(&mut self, line: impl AsRef<str>) {
        self.close(line);
        self.depth += 1;
    }

    /// Text as it is, no indentation added.
    pub fn raw(&mut self, text: impl AsRef<str>) {
        self.text.push_str(text.as_ref());
    }

    /// The text written.
    #[must_use]
    pub fn finish(self) -> String {
        self.text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_language_spells_a_declaration_and_a_signature() {
        let all = [Language::Wgsl, Language::Glsl, Language::Hlsl, Language::C];
        let lets = all.map(|l| l.let_(Type::Float, "x", "1.0"));
        assert_eq!(
            lets,
            [
                "let x = 1.0;",
                "float x = 1.0;",
                "float x = 1.0;",
                "const double x = 1.0;"
            ]
        );
        let sigs = all.map(|l| {
            l.signature(
                Some(Type::Vec3),
                "f",
                &[(Type::Vec3, "n"), (Type::Float, "a")],
            )
        });
        assert_eq!(
            sigs,
            [
                "fn f(n: vec3<f32>, a: f32) -> vec3<f32>",
                "vec3 f(vec3 n, float a)",
                "float3 f(float3 n, float a)",
                "static inline void f(const double n[3], double a, double out[3])",
            ]
        );
        assert_eq!(Language::C.constant(Type::Int, "N", "3"), "#define N 3");
        assert_eq!(
            Language::Hlsl.array_open(Type::Vec3, "A", "2"),
            "static const float3 A[2] = {"
        );
    }

    #[test]
    fn each_language_spells_every_construct_its_own_way() {
        use Language::*;
        let all = [Wgsl, Glsl, Hlsl, C];
        let check = |what: &str, got: [String; 4], want: [&str; 4]| {
            for (lang, (g, w)) in all.iter().zip(got.iter().zip(want)) {
                assert_eq!(g, w, "{what} in {lang:?}");
            }
        };
        check(
            "var",
            all.map(|l| l.var(Type::Float, "w", "1.0")),
            [
                "var w = 1.0;",
                "float w = 1.0;",
                "float w = 1.0;",
                "double w = 1.0;",
            ],
        );
        check(
            "typed var",
            all.map(|l| l.var_typed(Type::Float, "w", "1.0")),
            [
                "var w: f32 = 1.0;",
                "float w = 1.0;",
                "float w = 1.0;",
                "double w = 1.0;",
            ],
        );
        check(
            "cast",
            all.map(|l| l.cast(Type::Float, "2 * m")),
            [
                "f32(2 * m)",
                "float(2 * m)",
                "float(2 * m)",
                "(double)(2 * m)",
            ],
        );
        check(
            "vector",
            all.map(|l| l.vector(Type::Vec3, "1.0, 2.0, 3.0")),
            [
                "vec3<f32>(1.0, 2.0, 3.0)",
                "vec3(1.0, 2.0, 3.0)",
                "float3(1.0, 2.0, 3.0)",
                "{1.0, 2.0, 3.0}",
            ],
        );
        check(
            "vector constant",
            all.map(|l| l.constant(Type::Vec3, "SHLIGHT_Z", "v")),
            [
                "const SHLIGHT_Z: vec3<f32> = v;",
                "const vec3 SHLIGHT_Z = v;",
                "static const float3 SHLIGHT_Z = v;",
                "static const double shlight_z[3] = v;",
            ],
        );
        check(
            "array",
            all.map(|l| {
                format!(
                    "{}..{}",
                    l.array_open(Type::Float, "A", "2"),
                    l.array_close()
                )
            }),
            [
                "var<private> A: array<f32, 2> = array<f32, 2>(..);",
                "const float A[2] = float[2](..);",
                "static const float A[2] = {..};",
                "static const double a[2] = {..};",
            ],
        );
        check(
            "private array",
            all.map(|l| l.private_array(Type::IVec3, "g", 8)),
            [
                "var<private> g: array<vec3<i32>, 8>;",
                "ivec3 g[8];",
                "static int3 g[8];",
                "static int g[8][3];",
            ],
        );
        check(
            "select",
            all.map(|l| l.select("a", "b", "c")),
            ["select(a, b, c)", "c ? b : a", "c ? b : a", "c ? b : a"],
        );
        check(
            "loop",
            all.map(|l| l.for_open("k", "0", "k < 8", true)),
            [
                "for (var k: i32 = 0; k < 8; k++) {",
                "for (int k = 0; k < 8; k++) {",
                "for (int k = 0; k < 8; k++) {",
                "for (int k = 0; k < 8; k++) {",
            ],
        );
        check(
            "clamp",
            all.map(|l| l.clamp("v", "-1.0", "1.0")),
            [
                "clamp(v, -1.0, 1.0)",
                "clamp(v, -1.0, 1.0)",
                "clamp(v, -1.0, 1.0)",
                "fmin(fmax(v, -1.0), 1.0)",
            ],
        );
        // Lane by lane where the language selects only whole values.
        assert_eq!(
            Wgsl.select_lanes(
                Type::Vec3,
                Lanes::OneMinus("t"),
                Lanes::Name("t"),
                Lanes::Name("up")
            ),
            "select(vec3<f32>(1.0) - t, t, up)"
        );
        assert_eq!(
            Glsl.select_lanes(
                Type::Vec2,
                Lanes::Splat("-1.0"),
                Lanes::Splat("1.0"),
                Lanes::Compare("q", ">=", "0.0")
            ),
            "vec2(q.x >= 0.0 ? 1.0 : -1.0, q.y >= 0.0 ? 1.0 : -1.0)"
        );
        assert_eq!(
            Wgsl.select_all(Type::Vec2, "q", "f", "d.z < 0.0"),
            "select(q, f, vec2<bool>(d.z < 0.0))"
        );
        assert_eq!(
            Glsl.select_all(Type::Vec2, "q", "f", "d.z < 0.0"),
            "d.z < 0.0 ? f : q"
        );
    }

    #[test]
    fn code_indents_blocks() {
        let mut c = Code::new();
        c.open("if (a) {");
        c.line("b;");
        c.reopen("} else {");
        c.line("");
        c.close("}");
        assert_eq!(c.finish(), "if (a) {\n    b;\n} else {\n\n}\n");
    }
}
