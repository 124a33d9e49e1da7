//! The `nurbsCurve` and `nurbsSurface` shape nodes: authored (or connected) geometry in,
//! the validated geometry in local and world space and its description out.

use std::sync::Arc;

use glam::DMat4;
use sinew_core::{
    ComputeContext, ComputeError, Curve, CurveForm, Input, MultiOutput, NodeSpec, NodeType, Output, SpecBuilder,
    SpecError, Surface,
};

use super::basis::Direction;
use super::curve_eval::CurveEval;
use super::surface_eval::SurfaceEval;

/// Maya's `form` choices of curves and surfaces, by index.
pub const FORMS: [&str; 3] = ["open", "closed", "periodic"];

/// The outputs describing one parametric direction.
#[derive(Clone, Copy, Debug)]
struct DirOutputs {
    degree: Output<i64>,
    spans: Output<i64>,
    form: Output<i64>,
    min: Output<f64>,
    max: Output<f64>,
}

impl DirOutputs {
    fn declare(b: &mut SpecBuilder, suffix: &str) -> Self {
        let degree = b.output(&format!("degree{suffix}"), 0i64);
        let spans = b.output(&format!("spans{suffix}"), 0i64);
        let form = b.output_enum(&format!("form{suffix}"), &FORMS, 0);
        let min = b.output(&format!("minValue{suffix}"), 0.0);
        let max = b.output(&format!("maxValue{suffix}"), 0.0);
        b.attr_doc(degree, "degree (0 while there is no geometry)")
            .attr_doc(spans, "number of spans")
            .attr_doc(
                form,
                "open, closed (open with the first and last points equal) or periodic",
            )
            .attr_doc(min, "start of the parameter domain")
            .attr_doc(max, "end of the parameter domain");
        DirOutputs {
            degree,
            spans,
            form,
            min,
            max,
        }
    }

    fn ids(&self) -> [sinew_core::AttrId; 5] {
        [
            self.degree.id(),
            self.spans.id(),
            self.form.id(),
            self.min.id(),
            self.max.id(),
        ]
    }

    fn write(&self, ctx: &mut ComputeContext<'_>, d: Option<&Direction>, closed: bool) {
        let (degree, spans, form, (min, max)) = match d {
            Some(d) => (
                d.degree() as i64,
                d.spans() as i64,
                if d.is_periodic() { 2 } else { i64::from(closed) },
                d.domain(),
            ),
            None => (0, 0, 0, (0.0, 0.0)),
        };
        ctx.set(self.degree, degree);
        ctx.set(self.spans, spans);
        ctx.set(self.form, form);
        ctx.set(self.min, min);
        ctx.set(self.max, max);
    }
}

/// Writes `value` to every existing element of `h`.
fn write_all<T: sinew_core::AttrValue + Clone>(ctx: &mut ComputeContext<'_>, h: MultiOutput<T>, value: T) {
    for k in 0..ctx.multi_out_len(h) {
        ctx.set_elem(h, k, value.clone());
    }
}

/// `nurbsCurve`: a curve shape (Maya's node of that name).
///
/// `create` (the curve: authored in the rig file, or connected from a node that makes
/// curves) is validated (degree 1..=7, enough finite control points, knots) and passed on
/// as `local`; `worldSpace[i]` is the curve with every control point transformed by
/// `worldMatrix` (connect the parent transform's worldMatrix; B-splines are affine
/// invariant, so this is exact). Describing outputs: `degree`, `spans`, `form` (0 open, 1
/// closed: open with equal first and last points, 2 periodic), `minValue`, `maxValue`
/// (the domain). A curve with no control points (the default) passes through with degree
/// 0; any other invalid curve is an error naming the problem. Maya's `worldSpace` is
/// indexed by instance; sinew has one instance, so every element holds the same curve.
pub struct NurbsCurve {
    spec: NodeSpec,
    create: Input<Arc<Curve>>,
    world_matrix: Input<DMat4>,
    local: Output<Arc<Curve>>,
    world_space: MultiOutput<Arc<Curve>>,
    info: DirOutputs,
}

impl NurbsCurve {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("nurbsCurve");
        // Maya's short names (node reference and Maya-written files: curveShape.ws -> motionPath.gp).
        b.maya_names(&[
            ("create", "cr"),
            ("local", "l"),
            ("worldSpace", "ws"),
            ("degree", "d"),
            ("form", "f"),
            ("worldMatrix", "wm"),
        ]);
        b.doc("a NURBS curve shape: create → local and worldSpace[i] (transformed by worldMatrix)");
        let create = b.input("create", Arc::new(Curve::default()));
        let world_matrix = b.input("worldMatrix", DMat4::IDENTITY);
        let local = b.output("local", Arc::new(Curve::default()));
        let world_space = b.multi_output("worldSpace", Arc::new(Curve::default()));
        let info = DirOutputs::declare(&mut b, "");
        b.attr_doc(create, "the curve in object space (degree, points, knots, form)")
            .attr_doc(
                world_matrix,
                "object-to-world matrix (the parent transform's worldMatrix)",
            )
            .attr_doc(local, "create, validated")
            .attr_doc(world_space, "the curve in world space");
        b.affects(&[create.id()], &[local.id()]);
        b.affects(&[create.id(), world_matrix.id()], &[world_space.id()]);
        b.affects(&[create.id()], &info.ids());
        Ok(NurbsCurve {
            spec: b.build()?,
            create,
            world_matrix,
            local,
            world_space,
            info,
        })
    }
}

/// The validated evaluator of `c`, `None` for a curve without points; errors name `what`.
fn check_curve(c: &Curve, what: &str) -> Result<Option<CurveEval>, ComputeError> {
    if c.points.is_empty() {
        return Ok(None);
    }
    CurveEval::new(c)
        .map(Some)
        .map_err(|e| ComputeError::new(format!("{what}: {e}")))
}

impl NodeType for NurbsCurve {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let c = ctx.get(self.create);
        let eval = check_curve(&c, "nurbsCurve.create")?;
        if ctx.wants(self.world_space) {
            let m = ctx.get(self.world_matrix);
            let world = if m == DMat4::IDENTITY {
                c
            } else {
                let mut w = (*c).clone();
                w.points.iter_mut().for_each(|p| *p = m.transform_point3(*p));
                Arc::new(w)
            };
            write_all(ctx, self.world_space, world);
        } else {
            // `local` and the description depend on `create` alone: one compute group.
            let closed = c.form == CurveForm::Open && c.points.len() > 1 && c.points.first() == c.points.last();
            self.info.write(ctx, eval.as_ref().map(|e| e.direction()), closed);
            ctx.set(self.local, c);
        }
        Ok(())
    }
}

/// `nurbsSurface`: a surface shape (Maya's node of that name), for ribbons.
///
/// As [`NurbsCurve`], per direction: `create` (the surface: degrees, forms, a grid of
/// control points, knots) is validated and passed on as `local` and, transformed by
/// `worldMatrix`, as `worldSpace[i]`; `degreeU`/`degreeV`, `spansU`/`spansV`,
/// `formU`/`formV` and the domains `minValueU`, `maxValueU`, `minValueV`, `maxValueV`
/// describe it (Maya's `minMaxRangeU`/`V` pairs, flattened). A surface with no control
/// points passes through with degrees 0; any other invalid one is an error.
pub struct NurbsSurface {
    spec: NodeSpec,
    create: Input<Arc<Surface>>,
    world_matrix: Input<DMat4>,
    local: Output<Arc<Surface>>,
    world_space: MultiOutput<Arc<Surface>>,
    info_u: DirOutputs,
    info_v: DirOutputs,
}

impl NurbsSurface {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut b = NodeSpec::builder("nurbsSurface");
        b.maya_names(&[
            ("create", "cr"),
            ("local", "l"),
            ("worldSpace", "ws"),
            ("worldMatrix", "wm"),
        ]);
        b.doc("a NURBS surface shape: create → local and worldSpace[i] (transformed by worldMatrix)");
        let create = b.input("create", Arc::new(Surface::default()));
        let world_matrix = b.input("worldMatrix", DMat4::IDENTITY);
        let local = b.output("local", Arc::new(Surface::default()));
        let world_space = b.multi_output("worldSpace", Arc::new(Surface::default()));
        let info_u = DirOutputs::declare(&mut b, "U");
        let info_v = DirOutputs::declare(&mut b, "V");
        b.attr_doc(
            create,
            "the surface in object space (degreeU/V, formU/V, points rows, knotsU/V)",
        )
        .attr_doc(
            world_matrix,
            "object-to-world matrix (the parent transform's worldMatrix)",
        )
        .attr_doc(local, "create, validated")
        .attr_doc(world_space, "the surface in world space");
        b.affects(&[create.id()], &[local.id()]);
        b.affects(&[create.id(), world_matrix.id()], &[world_space.id()]);
        let mut info = info_u.ids().to_vec();
        info.extend(info_v.ids());
        b.affects(&[create.id()], &info);
        Ok(NurbsSurface {
            spec: b.build()?,
            create,
            world_matrix,
            local,
            world_space,
            info_u,
            info_v,
        })
    }
}

/// The validated evaluator of `s`, `None` for a surface without points; errors name `what`.
pub(crate) fn check_surface(s: &Surface, what: &str) -> Result<Option<SurfaceEval>, ComputeError> {
    if s.points.is_empty() && s.count_u == 0 && s.count_v == 0 {
        return Ok(None);
    }
    SurfaceEval::new(s)
        .map(Some)
        .map_err(|e| ComputeError::new(format!("{what}: {e}")))
}

impl NodeType for NurbsSurface {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let s = ctx.get(self.create);
        let eval = check_surface(&s, "nurbsSurface.create")?;
        if ctx.wants(self.world_space) {
            let m = ctx.get(self.world_matrix);
            let world = if m == DMat4::IDENTITY {
                s
            } else {
                let mut w = (*s).clone();
                w.points.iter_mut().for_each(|p| *p = m.transform_point3(*p));
                Arc::new(w)
            };
            write_all(ctx, self.world_space, world);
        } else {
            let cv = s.count_v.max(1) as usize;
            let rows_equal =
                |i: usize, j: usize| s.points.get(i * cv..(i + 1) * cv) == s.points.get(j * cv..(j + 1) * cv);
            let closed_u = s.count_u > 1 && rows_equal(0, s.count_u as usize - 1);
            let closed_v = s.count_v > 1 && s.points.chunks(cv).all(|r| r.first() == r.last());
            self.info_u.write(ctx, eval.as_ref().map(|e| e.dir_u()), closed_u);
            self.info_v.write(ctx, eval.as_ref().map(|e| e.dir_v()), closed_v);
            ctx.set(self.local, s);
        }
        Ok(())
    }
}
