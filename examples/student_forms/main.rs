//! A student's tracer with one mistake written in a form of its own: not the way check's fault
//! library plants it, so that check's tests can show a fit naming what no list holds.
//!
//! ```sh
//! cargo run --release --example student_forms -- FORM -input scene.txt -size 200 200 -output out.tga
//! ```
//!
//! FORM is one of the names in [`Form::named`]; the rest is the course's command line.

mod camera;
mod highlight;
mod picture;
mod reading;
mod sample;
mod textures;
mod trace;

use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use raycast::Scene;
use raycast::job::{Command, parse_args, render_to_files, reserve_outputs};
use raycast::parse::read_scene;
use raycast::{UVec3, Vec3A};

/// Each mistake, as a student might have written it.
#[derive(Debug, Clone, Copy)]
enum Form {
    /// Perspective rays at equal angle steps, a tangent per axis:
    /// `direction + tan((u - 0.5) * angle) * horizontal + tan((v - 0.5) * angle) * up`.
    TangentPerAxis,
    /// The up vector made orthogonal to the direction (`up - (up . d) d`) and never normalised.
    UpOrthogonalNotNormalised(Vec3A),
    /// The horizontal vector `direction x up` never normalised (the up vector made from it is).
    HorizontalNotNormalised(Vec3A),
    /// The screen built from the file's direction as written, not normalised.
    RawDirection(Vec3A),
    /// Half a pixel added to the row but not to the column.
    LeftEdge,
    /// The depth picture's grey counted from the picture's nearest hit, over the command line's
    /// range: `1 - (t - nearest) / (TMAX - TMIN)`.
    DepthFromNearest(f32),
    /// A Transform's normal carried as the 4-vector (n, 0) by the whole inverse transpose and
    /// normalised with its fourth component, whose first three are then the normal: shortened
    /// wherever the translation leans on it.
    NormalFourVector,
    /// Two mistakes of the shading sum at once: the ambient term inside the loop over the
    /// lights, and each light's diffuse term written `kd * light * pow(max(N.L, 0), 2)`.
    AmbientInLoopCosineSquared,
    /// Shadow, mirror and glass rays started at `point + 1e-7 * normal`: the t of that point
    /// along the ray, `1e-7 / |d.n|`.
    TinyNormalOffset,
    /// Each filter's reach (the box's and the tent's radius, the Gaussian's sigma) half a
    /// pixel more than the command line says.
    FilterHalfPixelWider,
    /// Marble's veins as `sin(2 pi frequency x + amplitude noise)`: the file's frequency taken
    /// as turns per unit, not radians.
    MarbleInTurns,
    /// Marble's stripes across y: `sin(frequency * y + amplitude * N)`.
    MarbleAlongY,
    /// A point light dimmed as light falls off in the world, `colour / (d * d)`, whatever the
    /// file's attenuation says.
    InverseSquareLight,
    /// Snell's law in Heckbert's form, `c1 = -n.d`, `c2 = sqrt(1 - eta^2 (1 - c1^2))`,
    /// `t = eta d + (eta c1 - c2) n`, with n the surface's outward normal on both sides: never
    /// turned when the ray leaves the glass.
    HeckbertOutwardNormal,
    /// The same form with the normal turned to the ray, but `c1 = n.d`: the cosine's minus
    /// forgotten.
    HeckbertCosineSign,
    /// The shadow ray toward a point light made with a unit direction and tested for hits
    /// with `t < 1 - epsilon`, as for the unnormalised direction `light - point`.
    ShadowToOneMinusEpsilon,
    /// The mirror direction as the textbook's `2 (N.V) N - V`, with V the ray's own direction
    /// where the formula means the direction back toward the eye.
    ReflectViewVector,
    /// The mirror direction `d - (d.n) n`, normalised: the 2 forgotten.
    ReflectWithoutTwo,
    /// Snell's ratio `1 / index` on both sides of the glass: never turned when the ray leaves.
    RatioNeverFlipped,
    /// Snell's ratio `index / 1` on both sides of the glass.
    RatioIndexBothWays,
    /// Past the critical angle the square root of a negative number: a direction of NaNs,
    /// which finds nothing and brings back the background.
    TotalInternalNan,
    /// Past the critical angle the glass ray is sent along the mirror direction instead,
    /// weighed by the transparent colour.
    TotalInternalMirror,
    /// The mirror ray's colour weighed by the reflective colour twice (once where the ray is
    /// made, once where its colour is added).
    MirrorColourTwice,
    /// The recursion's own test for a miss, written apart from the camera's: a mirror or glass
    /// ray that hits nothing adds nothing (black), where the camera's ray sees the background.
    MissesAddNothing,
    /// `if (reflective) colour = reflective * trace(mirror ray); else colour = shading`: a
    /// mirror or glass shows no shading of its own.
    MirrorOrShading,
    /// The shading mixed with what the mirror and glass rays bring back, `(1 - kr - kt) *
    /// shading`, each channel at least 0.
    ShadingMixedWithMirror,
    /// The pixel loop's indices swapped: pixel (i, j) gets the ray of (j, i).
    LoopsSwapped,
    /// The indices swapped and the rows counted from the top: pixel (i, j) gets the ray of
    /// (height − 1 − j, i), a quarter turn.
    LoopsSwappedFromTheTop,
    /// The sphere test returns `(-b - sqrt(d)) / 2a` if it is past t_min, else nothing: a
    /// ray from inside a sphere never meets it.
    SphereMinusRootOnly,
    /// The sphere test returns `(-b + sqrt(d)) / 2a`, the sign of the root written the wrong
    /// way round.
    SpherePlusRootOnly,
    /// The shadow ray made as `Ray(point, point - lightPosition)`, normalised, or along a
    /// directional light's direction as the file gives it: from the light, not toward it.
    ShadowFromTheLight,
    /// The shadow ray toward a point light made as `Ray(point, point - lightPosition)`; toward
    /// a directional light, right.
    PointShadowFromTheLight,
    /// The mirror's and glass's colours added inside the loop over the lights (the
    /// ambient term before it).
    MirrorsInTheLightLoop,
    /// Two mistakes at once: the ambient term inside the loop over the lights, and each
    /// light's diffuse term never clamped (`kd * light * N.L`).
    AmbientInLoopNeverClamped,
    /// traceRay intersects first and only then returns black for `bounces > max_bounces`: a
    /// mirror or glass ray one past the limit that meets nothing returns the background.
    BouncesTestedAfterTheHit,
    /// Each mirror and glass ray traced with `traceRay(..., bounces, ...)`: the depth never
    /// counted, so only the weight stops the recursion.
    BouncesNeverCounted,
    /// traceRay intersects first, then tests `bounces > max_bounces` and `weight < cutoff`.
    LimitsTestedAfterTheHit,
    /// The shading sum started with `color = ambientLight`, the diffuse colour forgotten.
    AmbientLightAlone,
    /// Each light's diffuse term `kd * light * N.L`, the `max(0, ...)` forgotten: a light
    /// behind the surface darkens it (the highlight gated as the course's).
    DiffuseNeverClamped,
    /// The Transform's ray carried with `Matrix::Transform(Vec4f(direction, 1))`: the
    /// inverse's translation added to the direction.
    DirectionCarriedAsPoint,
    /// The Transform's ray carried by the matrix as the file composes it, never inverted.
    RaysByTheMatrix,
    /// The Transform's ray origin carried with `TransformDirection`: its translation lost (the
    /// reader keeps each object's matrix without its translation, the normals' matrix is the
    /// same either way).
    RaysLoseTheTranslation,
    /// A texture's `getDiffuseColor()` without the point is the base class's colour, black:
    /// textured objects get no ambient light.
    TextureAmbientBlack,
    /// A texture's `getDiffuseColor()` without the point answers with its first material's.
    TextureAmbientFirstMaterial,
    /// The recursion passes t_min 0 to the mirror and glass rays, where the shadow test passes
    /// the course's offset.
    SecondaryFromZero,
    /// The shadow test starts at t = 0, where the mirror and glass rays start off the surface.
    ShadowsFromZero,
    /// Only the mirror ray's miss adds nothing: the glass ray goes through `traceRay`, whose
    /// miss is the background.
    MirrorMissAddsNothing,
    /// The checkerboard's cells counted with C's `fmod(x, 2) < 1` per axis, which is true for
    /// every negative coordinate.
    CheckerFmod,
    /// The checkerboard's cells counted from `floor(|x|)`: mirrored about each axis.
    CheckerAbsolute,
    /// Uniform samples spread from edge to edge of the pixel, `a / (s - 1)`.
    UniformEdgeToEdge,
    /// The attenuation's three numbers read in the other order: `1 / (q + l d + c d^2)`.
    AttenuationReversed,
    /// Shadow, mirror and glass rays started `1e-6` along themselves, however large the
    /// scene's coordinates.
    AbsoluteEpsilonAlongRay,
    /// The Gaussian written `exp(-d^2 / (2 sigma))`: the file's sigma taken as the variance.
    GaussianVarianceAsSigma,
    /// Rows counted from the top of the picture where the camera counts from the bottom.
    RowsFromTheTop,
    /// The horizontal vector made as `up x direction`, the cross product's order reversed.
    HorizontalReversed,
    /// Columns spread over `width - 1`, `i / (width - 1)`; rows through their centres.
    ColumnsOverWidthMinusOne,
    /// Rays through each pixel's upper-right corner, `(i + 1) / width`.
    FarCorner,
    /// The perspective screen as wide as the angle in radians at distance 1, not
    /// `2 tan(angle / 2)`.
    ScreenAsWideAsTheAngle,
    /// The depth picture's grey counted from the command line's near end to the picture's
    /// farthest hit.
    DepthToFarthest(f32),
    /// The normals picture as `(n + 1) / 2`, the way normal maps are stored.
    NormalsHalfPlusHalf,
    /// Each light's colour scaled by `N.L` where it arrives, before the diffuse and specular
    /// terms (which take `N.L` again).
    LightScaledByCosine,
    /// The recursion's depth counted from 1, so `-bounces N` traces N - 1 levels.
    DepthCountedFromOne,
    /// The noise's octaves summed from the second, `noise(2^i p) / 2^i` for i = 1 to octaves.
    NoiseFromSecondOctave,
    /// The picture's bytes written blue, green, red into a writer that takes red first.
    BlueGreenRed,
    /// Bytes made with a cast to `unsigned char` and no clamp: past 255 they wrap.
    BytesWrap,
    /// The normals picture's colour `max(n, 0)` per component: the negative ones black.
    NormalsClampedAtZero,
    /// The depth and normals pictures' misses in the scene's background colour.
    MissesInBackground,
    /// Back faces black, `-shade_back` or not.
    BackFacesAlwaysBlack,
    /// Back faces shaded from their other side, `-shade_back` or not.
    BackFacesAlwaysShaded,
    /// Without `-shade_back`, back faces given the ambient term before the test that blacks
    /// them out.
    BackFacesAmbient,
    /// The ambient term added only in a scene without lights.
    AmbientOnlyWithoutLights,
    /// The ambient term times the number of lights (at least one).
    AmbientTimesLights,
    /// Each light's terms with the normal turned toward the light: lit from both sides.
    NormalTurnedToTheLight,
    /// Shadow rays toward point lights tested to infinity.
    ShadowToInfinity,
    /// Mirrors and glass: `-bounces` never read, so no mirror or glass ray is traced.
    BouncesUnread,
    /// Glass: the refracted ray never traced (its contribution left at zero).
    GlassNeverTraced,
    /// Shadows: `-shadows` never read, so no shadow ray is cast.
    ShadowsFlagUnread,
    /// Shadows: the shadow ray's tmax left at 0 (its Hit made with t = 0, never set to the
    /// light's distance), so it meets nothing.
    ShadowRayOfNoLength,
    /// `-weight` never read: every mirror and glass ray traced.
    EveryRayTraced,
    /// Jittered samples anywhere in the pixel, from a generator of the student's own.
    JitterAnywhere,
    /// The filter's weighted sum divided by the number of samples it weighed.
    WeightsOverCount,
    /// The filter weighs the pixel's own samples alone: a neighbour's sample weighs nothing.
    FilterOwnPixel,
    /// The neighbours gathered by `for (d = -r; d < r; d++)`: the samples of the last
    /// neighbour on each axis weigh nothing.
    NeighboursLoopShort,
    /// The perspective camera's rays take hits from minus infinity on: behind the eye too.
    HitsBehindTheEye,
    /// Textures evaluated at the world point, the texture's own Transform never applied.
    TextureMatrixIgnored,
    /// A Transform's normal carried by the object's own matrix, then normalised.
    NormalByObjectMatrix,
    /// The nearest hit searched from t = 50 down: farther surfaces lost.
    FarthestFifty,
    /// Camera rays started at the depth picture's near end (the command line's TMIN), as if
    /// it bounded the search: what is nearer is cut away.
    DepthNearAsStart(f32),
    /// The depth picture's grey cast to `unsigned char` unclamped: past either end it wraps.
    DepthWraps,
    /// The highlight faded by `N.L` whether or not the line asks for `-specular_fix`.
    SpecularAlwaysFaded,
    /// The recursion's test `depth <= bounces` with the depth counted from 0: a level more.
    OneBounceMore,
    /// Uniform samples at the upper-right corners of the grid's cells, `(a + 1) / s`.
    UniformUpperCorners,
    /// The filter's weighted sum divided by the pixel's own number of samples.
    WeightsOverPixelSamples,
    /// The filter weighs a sample by its distance from the pixel's lower-left corner, `(i, j)`,
    /// not from its centre, `(i + 0.5, j + 0.5)`.
    FilterFromCorner,
    /// The same with the rows counted from the picture's top: the distance from the pixel's
    /// upper-left corner.
    FilterFromTopCorner,
    /// Noise's and Marble's values taken as the weight itself, not mapped by (1 + x) / 2.
    NoiseUnmapped,
    /// Noise and Marble interpolated as `N * first + (1 - N) * second`: the materials'
    /// places exchanged.
    NoiseBlendedTheOtherWay,
    /// The highlight `ks * (N.H)^q` added as it is, never times the light's colour.
    HighlightWithoutLightColour,
    /// The Gaussian written `exp(-d² / σ²)`, the 2 left out, still cut at 2σ.
    GaussianWithoutTwo,
    /// The Gaussian written `exp(-d² / (2σ))`, σ not squared, still cut at 2σ.
    GaussianSigmaUnsquared,
    /// The texture's point taken through the inverse of its Transform.
    TextureMatrixInverted,
    /// Shadow rays toward point lights made with the unnormalised `light - point` and tested
    /// up to t = the light's distance: the distance squared along a unit direction.
    ShadowToDistanceSquared,
    /// The orthographic camera's rays take hits from t = 0 on: nothing behind its centre.
    OrthographicFromZero,
    /// A Transform's normal carried by the inverse transpose and never made unit again.
    NormalNotRenormalised,
    /// Perspective rays turned up or down by `y a`, then left or right by `x a`:
    /// `cos(x a) cos(y a) d + sin(x a) h + cos(x a) sin(y a) up`.
    SphericalRays,
    /// The view's v counted from the top, `1 - (j + 0.5) / height`.
    VFromTheTop,
    /// The view's u mirrored, `1 - (i + 0.5) / width`.
    UMirrored,
    /// What a glass ray brings back added whole, not times the transparent colour.
    GlassColourIgnored,
    /// The highlight `pow(max(N.H, 0), q)` added for every light, in front of the surface or
    /// behind it.
    HighlightUngated,
    /// The highlight `pow(fabs(N.H), q)` added for every light.
    HighlightAbsolute,
    /// The half vector `(L + V) / 2`, the mean of the two: shorter than a unit wherever they
    /// part.
    HalfVectorHalved,
    /// Phong's `pow(max(R.V, 0), q)` with V the ray's direction, R the light's mirrored.
    MirrorAgainstTheRay,
    /// A Transform's normal carried by the inverse matrix, not its transpose, then normalised.
    NormalByInverse,
    /// A Transform's normal carried by the transpose of the object's matrix (the inverse
    /// forgotten), then normalised.
    NormalByTranspose,
    /// A ray's weight carried as the product of its colours' mean channels.
    WeightByMeanChannel,
    /// A ray's weight carried as the product of its colours' greatest channels.
    WeightByGreatestChannel,
    /// Triangles by Moller and Trumbore's test, a hit refused where `u` or `v` is below `5e-3`
    /// or their sum above `1 - 5e-3`: cracks along every edge.
    MollerTrumboreEdges,
    /// Triangles by Moller and Trumbore's test, a hit refused where `fabs(det) < 1e-3`.
    MollerTrumboreDeterminant,
    /// Normals never turned toward the ray, and back faces shaded like any other.
    NormalsNeverTurned,
    /// The loop over the lights `for (i = 0; i < n - 1; i++)`.
    LightLoopShort,
    /// The loop over the lights returns once the first light's terms are added (a `return`
    /// inside the loop).
    FirstLightOnly,
    /// The grid walked cell by cell, the walk ended at the first cell in which any object is
    /// hit, wherever along the ray the hit lies.
    GridTrustsFirstHit,
    /// The grid walked with a mailbox: each object tested once per ray, its hit kept only if
    /// it lies within the cell that tested it.
    GridMailbox,
    /// Grid: an object under a Transform entered by its box's two corners carried and sorted.
    GridBoxOfTwoCorners,
    /// Grid: an object under a Transform entered by its own space's box.
    GridBoxInItsOwnSpace,
    /// Grid: a sphere entered in the cells whose centres lie inside it (the handout's test
    /// without its conservative margin).
    GridSphereCentresInside,
    /// Grid: every object entered in the cells from its box's lowest corner's up to, and not
    /// including, its highest corner's (a loop's bound written with `<`).
    GridCellsUpperLeftOut,
    /// Grid: the student's own march, each step along an axis the ray runs down written
    /// `dt = size / d`, the absolute value forgotten.
    GridStepNotAbsolute,
    /// Grid: the student's own march, the first crossing on every axis at `(i + 1) * size`.
    GridUpperFaceAlways,
    /// Grid: a ray whose origin falls in one of the grid's cells left out of the march.
    GridOriginCellLeftOut,
    /// Grid: a ray whose origin lies within the grid's box left out of the march.
    GridOriginInsideLeftOut,
    /// Grid: a ray left out of the march where a slab test of the grid's box finds its entry
    /// behind its origin (t ≤ 0), the student's test of an origin inside the box, which also
    /// takes some rays starting a rounding outside for inside.
    GridOriginInSlabsLeftOut,
    /// A grid walk that tests only what its cells list: the planes, which have no box, are
    /// never tested.
    GridWithoutPlanes,
    /// The plane's equation written n·P + d = 0: t = -(d + n·O) / (n·D).
    PlanePlusOffset,
    /// The shading sums `kd * max(N.L, 0)` for each light, the light's colour left out.
    LightColourLeftOut,
    /// The triangle's normal made as (c − a) × (b − a).
    CrossProductReversed,
    /// The planes put in the grid's cells they cross: a plane's hit counts only where it lies
    /// inside the grid's box.
    PlanesInGridCells,
    /// The noise's octaves summed without their weights, `noise(2^i p)` for i = 0 to
    /// octaves - 1.
    NoiseOctavesUnweighed,
    /// The tent's distance `fabs(dx) + fabs(dy)`.
    TentManhattan,
    /// The tent's distance `max(fabs(dx), fabs(dy))`.
    TentChebyshev,
    /// The box's test `dx * dx + dy * dy <= r * r`.
    BoxDisc,
    /// Jittered samples at each cell's centre moved by up to half a pixel, not half a cell:
    /// `(a + 0.5) / s + rand() - 0.5`, kept in the pixel.
    JitterAroundCells,
    /// Hits farther than 20 units along the ray dropped by the shading (`if (t > 20) return
    /// background`).
    NearestWithinTwenty,
    /// The diffuse term `kd * fabs(N.L)`; the highlight as the course's.
    DiffuseAbsolute,
    /// Screen coordinates centred on the view, `x = 2 i / (width - 1) - 1` and likewise for the
    /// rows: each runs from edge to edge of the view.
    CentredEdgeToEdge,
    /// Each object's t measured along its object-space ray made unit length, then carried back
    /// by multiplying by that ray's length where it should divide.
    ObjectTMultipliedBack,
    /// The clamp written before the scale, `(unsigned char)(255 * fmin(fmax(c, 0), 255))`: its
    /// bound in bytes where the value is still in [0, 1], so past 1 the byte wraps.
    ClampBeforeScaling,
    /// The depth picture's grey clamped the same way, to [0, 255] before it is scaled.
    DepthClampBeforeScaling,
    /// Every colour of the scene file read as blue, green, red.
    ColoursReadBlueFirst,
    /// The highlight weighed by the material's diffuse colour, not its specular colour (made
    /// while the scene is read).
    HighlightOfTheDiffuseColour,
    /// The highlight white, the light's colour alone, `specularColor` never multiplied in (made
    /// while the scene is read).
    HighlightLeftWhite,
    /// A mirror's ray weighed by the material's specular colour, not its reflective colour
    /// (made while the scene is read).
    MirrorOfTheSpecularColour,
    /// A glass ray weighed by the material's specular colour, not its transparent colour (made
    /// while the scene is read).
    GlassOfTheSpecularColour,
    /// The Background's `ambientLight` read into a local variable that hides the scene's own:
    /// the scene's ambient light stays black.
    AmbientNeverStored,
    /// The plane's offset read as the distance from the plane to the origin, the other way
    /// along the normal.
    PlaneOffsetNegated,
    /// The triangle's normal made from the edges leaving its second corner,
    /// `(a - b) x (c - b)`.
    EdgesFromTheMiddleCorner,
    /// Each light's colour taken as one brightness, its brightest channel, the same for red,
    /// green and blue.
    LightAsBrightestChannel,
    /// The highlight worked out with the diffuse term's cosine in it,
    /// `pow(max(N.H, 0), q) * max(N.L, 0)`, on every line.
    HighlightTimesCosine,
    /// Hits nearer than the depth picture's near end (the command line's TMIN) thrown away
    /// once found: what is behind them is not searched for.
    DepthNearDropsHits(f32),
    /// The highlight added for the scene's first light alone (its term written outside the
    /// loop over the lights, for `lights[0]`).
    HighlightFirstLightOnly,
    /// No highlight at all: the specular term never added.
    SpecularLeftOut,
    /// The highlight added after the loop over the lights with the loop's last light, the one
    /// its variable was left at.
    HighlightAfterTheLoop,
    /// A directional light's direction taken as the way toward the light, not the way its
    /// light travels: lit, and shadowed, from the other side.
    DirectionalNotNegated,
    /// The triangle's normal `(b - a) x (c - a)` never normalised: as long as twice the
    /// triangle's area.
    TriangleNormalUnnormalised,
    /// The orthographic camera's size taken as the half-width of what it sees.
    OrthographicHalfSize,
    /// The sphere's normal `p - c`, never divided by the radius.
    SphereNormalNotDivided,
    /// The triangle's normal made from the edges leaving its last corner, `(a - c) x (b - c)`,
    /// and never normalised.
    LastCornerNormalUnnormalised,
    /// A directional light's direction negated as the file is read (taken for the way toward
    /// the light), and so never turned where the shading needs it turned.
    DirectionReadReversed,
    /// The way toward a point light left unnormalised, `position - point`, in the shading and
    /// for the shadow ray (tested up to `t < 1 - 1e-4` along it).
    PointDirectionUnnormalised,
    /// The same unnormalised vector, with the shadow ray tested up to the light's distance
    /// along it: past the light, a distance squared away.
    PointVectorToDistance,
    /// No mistake: a correct tracer whose camera rays, mirror and glass directions are worked
    /// out in double precision (`Vec3d`), each then rounded to float.
    DoublePrecision,
}

impl Form {
    fn named(
        name: &str,
        file_up: Vec3A,
        file_direction: Vec3A,
        (nearest, farthest): (f32, f32),
        depth_near: f32,
    ) -> Option<Form> {
        Some(match name {
            "tangent_per_axis" => Form::TangentPerAxis,
            "up_orthogonal_not_normalised" => Form::UpOrthogonalNotNormalised(file_up),
            "horizontal_not_normalised" => Form::HorizontalNotNormalised(file_up),
            "raw_direction" => Form::RawDirection(file_direction),
            "left_edge" => Form::LeftEdge,
            "depth_from_nearest" => Form::DepthFromNearest(nearest),
            "normal_four_vector" => Form::NormalFourVector,
            "ambient_in_loop_cosine_squared" => Form::AmbientInLoopCosineSquared,
            "tiny_normal_offset" => Form::TinyNormalOffset,
            "filter_half_pixel_wider" => Form::FilterHalfPixelWider,
            "marble_in_turns" => Form::MarbleInTurns,
            "marble_along_y" => Form::MarbleAlongY,
            "inverse_square_light" => Form::InverseSquareLight,
            "double_precision" => Form::DoublePrecision,
            "heckbert_outward_normal" => Form::HeckbertOutwardNormal,
            "heckbert_cosine_sign" => Form::HeckbertCosineSign,
            "shadow_to_one_minus_epsilon" => Form::ShadowToOneMinusEpsilon,
            "reflect_view_vector" => Form::ReflectViewVector,
            "reflect_without_two" => Form::ReflectWithoutTwo,
            "ratio_never_flipped" => Form::RatioNeverFlipped,
            "ratio_index_both_ways" => Form::RatioIndexBothWays,
            "total_internal_nan" => Form::TotalInternalNan,
            "total_internal_mirror" => Form::TotalInternalMirror,
            "mirror_colour_twice" => Form::MirrorColourTwice,
            "misses_add_nothing" => Form::MissesAddNothing,
            "mirror_or_shading" => Form::MirrorOrShading,
            "shading_mixed_with_mirror" => Form::ShadingMixedWithMirror,
            "loops_swapped" => Form::LoopsSwapped,
            "loops_swapped_from_the_top" => Form::LoopsSwappedFromTheTop,
            "sphere_minus_root_only" => Form::SphereMinusRootOnly,
            "diffuse_never_clamped" => Form::DiffuseNeverClamped,
            "ambient_light_alone" => Form::AmbientLightAlone,
            "bounces_tested_after_the_hit" => Form::BouncesTestedAfterTheHit,
            "bounces_never_counted" => Form::BouncesNeverCounted,
            "limits_tested_after_the_hit" => Form::LimitsTestedAfterTheHit,
            "ambient_in_loop_never_clamped" => Form::AmbientInLoopNeverClamped,
            "mirrors_in_the_light_loop" => Form::MirrorsInTheLightLoop,
            "shadow_from_the_light" => Form::ShadowFromTheLight,
            "point_shadow_from_the_light" => Form::PointShadowFromTheLight,
            "direction_carried_as_point" => Form::DirectionCarriedAsPoint,
            "rays_by_the_matrix" => Form::RaysByTheMatrix,
            "rays_lose_the_translation" => Form::RaysLoseTheTranslation,
            "sphere_plus_root_only" => Form::SpherePlusRootOnly,
            "texture_ambient_black" => Form::TextureAmbientBlack,
            "texture_ambient_first_material" => Form::TextureAmbientFirstMaterial,
            "secondary_from_zero" => Form::SecondaryFromZero,
            "shadows_from_zero" => Form::ShadowsFromZero,
            "mirror_miss_adds_nothing" => Form::MirrorMissAddsNothing,
            "checker_fmod" => Form::CheckerFmod,
            "checker_absolute" => Form::CheckerAbsolute,
            "uniform_edge_to_edge" => Form::UniformEdgeToEdge,
            "attenuation_reversed" => Form::AttenuationReversed,
            "absolute_epsilon_along_ray" => Form::AbsoluteEpsilonAlongRay,
            "gaussian_variance_as_sigma" => Form::GaussianVarianceAsSigma,
            "rows_from_the_top" => Form::RowsFromTheTop,
            "orthographic_from_zero" => Form::OrthographicFromZero,
            "normal_not_renormalised" => Form::NormalNotRenormalised,
            "spherical_rays" => Form::SphericalRays,
            "v_from_the_top" => Form::VFromTheTop,
            "u_mirrored" => Form::UMirrored,
            "glass_colour_ignored" => Form::GlassColourIgnored,
            "depth_near_as_start" => Form::DepthNearAsStart(depth_near),
            "depth_wraps" => Form::DepthWraps,
            "specular_always_faded" => Form::SpecularAlwaysFaded,
            "one_bounce_more" => Form::OneBounceMore,
            "uniform_upper_corners" => Form::UniformUpperCorners,
            "weights_over_pixel_samples" => Form::WeightsOverPixelSamples,
            "filter_from_corner" => Form::FilterFromCorner,
            "filter_from_top_corner" => Form::FilterFromTopCorner,
            "gaussian_without_two" => Form::GaussianWithoutTwo,
            "noise_unmapped" => Form::NoiseUnmapped,
            "noise_blended_the_other_way" => Form::NoiseBlendedTheOtherWay,
            "highlight_without_light_colour" => Form::HighlightWithoutLightColour,
            "gaussian_sigma_unsquared" => Form::GaussianSigmaUnsquared,
            "texture_matrix_inverted" => Form::TextureMatrixInverted,
            "shadow_to_distance_squared" => Form::ShadowToDistanceSquared,
            "blue_green_red" => Form::BlueGreenRed,
            "bytes_wrap" => Form::BytesWrap,
            "normals_clamped_at_zero" => Form::NormalsClampedAtZero,
            "misses_in_background" => Form::MissesInBackground,
            "back_faces_always_black" => Form::BackFacesAlwaysBlack,
            "back_faces_always_shaded" => Form::BackFacesAlwaysShaded,
            "back_faces_ambient" => Form::BackFacesAmbient,
            "ambient_only_without_lights" => Form::AmbientOnlyWithoutLights,
            "ambient_times_lights" => Form::AmbientTimesLights,
            "normal_turned_to_the_light" => Form::NormalTurnedToTheLight,
            "shadow_to_infinity" => Form::ShadowToInfinity,
            "shadows_flag_unread" => Form::ShadowsFlagUnread,
            "bounces_unread" => Form::BouncesUnread,
            "glass_never_traced" => Form::GlassNeverTraced,
            "shadow_ray_of_no_length" => Form::ShadowRayOfNoLength,
            "every_ray_traced" => Form::EveryRayTraced,
            "jitter_anywhere" => Form::JitterAnywhere,
            "weights_over_count" => Form::WeightsOverCount,
            "filter_own_pixel" => Form::FilterOwnPixel,
            "neighbours_loop_short" => Form::NeighboursLoopShort,
            "hits_behind_the_eye" => Form::HitsBehindTheEye,
            "texture_matrix_ignored" => Form::TextureMatrixIgnored,
            "normal_by_object_matrix" => Form::NormalByObjectMatrix,
            "farthest_fifty" => Form::FarthestFifty,
            "horizontal_reversed" => Form::HorizontalReversed,
            "columns_over_width_minus_one" => Form::ColumnsOverWidthMinusOne,
            "far_corner" => Form::FarCorner,
            "screen_as_wide_as_the_angle" => Form::ScreenAsWideAsTheAngle,
            "depth_to_farthest" => Form::DepthToFarthest(farthest),
            "normals_half_plus_half" => Form::NormalsHalfPlusHalf,
            "light_scaled_by_cosine" => Form::LightScaledByCosine,
            "depth_counted_from_one" => Form::DepthCountedFromOne,
            "noise_from_second_octave" => Form::NoiseFromSecondOctave,
            "highlight_ungated" => Form::HighlightUngated,
            "normal_by_inverse" => Form::NormalByInverse,
            "noise_octaves_unweighed" => Form::NoiseOctavesUnweighed,
            "grid_trusts_first_hit" => Form::GridTrustsFirstHit,
            "grid_mailbox" => Form::GridMailbox,
            "grid_box_of_two_corners" => Form::GridBoxOfTwoCorners,
            "grid_box_in_its_own_space" => Form::GridBoxInItsOwnSpace,
            "grid_sphere_centres_inside" => Form::GridSphereCentresInside,
            "grid_cells_upper_left_out" => Form::GridCellsUpperLeftOut,
            "grid_origin_cell_left_out" => Form::GridOriginCellLeftOut,
            "grid_origin_inside_left_out" => Form::GridOriginInsideLeftOut,
            "grid_origin_in_slabs_left_out" => Form::GridOriginInSlabsLeftOut,
            "grid_step_not_absolute" => Form::GridStepNotAbsolute,
            "grid_upper_face_always" => Form::GridUpperFaceAlways,
            "grid_without_planes" => Form::GridWithoutPlanes,
            "plane_plus_offset" => Form::PlanePlusOffset,
            "light_colour_left_out" => Form::LightColourLeftOut,
            "cross_product_reversed" => Form::CrossProductReversed,
            "planes_in_grid_cells" => Form::PlanesInGridCells,
            "light_loop_short" => Form::LightLoopShort,
            "first_light_only" => Form::FirstLightOnly,
            "normals_never_turned" => Form::NormalsNeverTurned,
            "moller_trumbore_edges" => Form::MollerTrumboreEdges,
            "moller_trumbore_determinant" => Form::MollerTrumboreDeterminant,
            "weight_by_mean_channel" => Form::WeightByMeanChannel,
            "weight_by_greatest_channel" => Form::WeightByGreatestChannel,
            "tent_manhattan" => Form::TentManhattan,
            "tent_chebyshev" => Form::TentChebyshev,
            "box_disc" => Form::BoxDisc,
            "normal_by_transpose" => Form::NormalByTranspose,
            "jitter_around_cells" => Form::JitterAroundCells,
            "nearest_within_twenty" => Form::NearestWithinTwenty,
            "diffuse_absolute" => Form::DiffuseAbsolute,
            "highlight_absolute" => Form::HighlightAbsolute,
            "half_vector_halved" => Form::HalfVectorHalved,
            "mirror_against_the_ray" => Form::MirrorAgainstTheRay,
            "centred_edge_to_edge" => Form::CentredEdgeToEdge,
            "object_t_multiplied_back" => Form::ObjectTMultipliedBack,
            "clamp_before_scaling" => Form::ClampBeforeScaling,
            "depth_clamp_before_scaling" => Form::DepthClampBeforeScaling,
            "colours_read_blue_first" => Form::ColoursReadBlueFirst,
            "highlight_of_the_diffuse_colour" => Form::HighlightOfTheDiffuseColour,
            "highlight_left_white" => Form::HighlightLeftWhite,
            "mirror_of_the_specular_colour" => Form::MirrorOfTheSpecularColour,
            "glass_of_the_specular_colour" => Form::GlassOfTheSpecularColour,
            "ambient_never_stored" => Form::AmbientNeverStored,
            "plane_offset_negated" => Form::PlaneOffsetNegated,
            "edges_from_the_middle_corner" => Form::EdgesFromTheMiddleCorner,
            "light_as_brightest_channel" => Form::LightAsBrightestChannel,
            "highlight_first_light_only" => Form::HighlightFirstLightOnly,
            "specular_left_out" => Form::SpecularLeftOut,
            "highlight_after_the_loop" => Form::HighlightAfterTheLoop,
            "directional_not_negated" => Form::DirectionalNotNegated,
            "point_direction_unnormalised" => Form::PointDirectionUnnormalised,
            "point_vector_to_distance" => Form::PointVectorToDistance,
            "direction_read_reversed" => Form::DirectionReadReversed,
            "triangle_normal_unnormalised" => Form::TriangleNormalUnnormalised,
            "orthographic_half_size" => Form::OrthographicHalfSize,
            "sphere_normal_not_divided" => Form::SphereNormalNotDivided,
            "last_corner_normal_unnormalised" => Form::LastCornerNormalUnnormalised,
            "highlight_times_cosine" => Form::HighlightTimesCosine,
            "depth_near_drops_hits" => Form::DepthNearDropsHits(depth_near),
            _ => return None,
        })
    }
}

/// Whether the student's bytes are rounded to the nearest (`FORM+rounded`), not truncated as
/// the course's: a second, harmless difference beside the form's mistake.
static ROUNDED: AtomicBool = AtomicBool::new(false);

/// The line's samples a pixel (the student divides by it).
static PIXEL_SAMPLES: AtomicU32 = AtomicU32::new(1);

fn run(args: Vec<String>) -> Result<(), String> {
    let (form, course) = args
        .split_first()
        .ok_or("usage: student_forms FORM[+rounded] RAYTRACER-ARGUMENTS...")?;
    let form = match form.strip_suffix("+rounded") {
        Some(form) => {
            ROUNDED.store(true, Ordering::Relaxed);
            form
        }
        None => form,
    };
    let mut options = match parse_args(course.iter().map(Into::into).collect())? {
        Command::Render(options) => *options,
        _ => return Err("expected a render's command line".into()),
    };
    match form {
        "shadows_flag_unread" => options.trace.shadows = false,
        "bounces_unread" => options.trace.bounces = 0,
        _ => {}
    }
    let mut description = read_scene(&options.input).map_err(|e| e.to_string())?;
    reading::read_as(form, &mut description);
    let camera = description.camera;
    let raw_direction = written_direction(&options.input).unwrap_or(camera.direction.into());
    let mut scene = Scene::from_description(&description).map_err(|e| e.to_string())?;
    if let Some([x, y, z]) = options.grid {
        scene
            .world
            .use_grid(UVec3::new(x, y, z))
            .map_err(|e| e.to_string())?;
    }
    let hits = hit_range(&scene, options.width, options.height);
    let depth_near = options.depth.as_ref().map_or(0.0, |&(near, _, _)| near);
    let form = Form::named(form, camera.up.into(), raw_direction, hits, depth_near)
        .ok_or_else(|| format!("unknown form '{form}'"))?;
    PIXEL_SAMPLES.store(options.sampling.sampler.samples(), Ordering::Relaxed);
    let pending = reserve_outputs(&options).map_err(|e| e.to_string())?;
    render_to_files(&options, &scene, form, pending).map_err(|e| e.to_string())?;
    Ok(())
}

/// The distances of the nearest and the farthest hits of the rays through the pixels' centres.
fn hit_range(scene: &Scene, width: u32, height: u32) -> (f32, f32) {
    let camera = &scene.camera;
    let (mut nearest, mut farthest) = (f32::INFINITY, 0.0f32);
    for j in 0..height {
        for i in 0..width {
            let (u, v) = raycast::camera::pixel_to_screen(i, j, width, height);
            let ray = camera.ray(u, v);
            if let Some(hit) = scene.world.intersect(&ray, camera.t_min()) {
                let t = hit.t * ray.direction.length();
                nearest = nearest.min(t);
                farthest = farthest.max(t);
            }
        }
    }
    (nearest, farthest)
}

/// The camera's direction as the scene file writes it (the parser normalises it).
fn written_direction(path: &std::path::Path) -> Option<Vec3A> {
    let text = std::fs::read_to_string(path).ok()?;
    let mut words = text
        .split_whitespace()
        .skip_while(|w| *w != "direction")
        .skip(1);
    let mut next = || words.next()?.parse::<f32>().ok();
    Some(Vec3A::new(next()?, next()?, next()?))
}

fn main() -> ExitCode {
    match run(std::env::args().skip(1).collect()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("student_forms: {message}");
            ExitCode::FAILURE
        }
    }
}
