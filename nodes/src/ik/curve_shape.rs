//! The `nurbsCurve` shape node: a curve in its transform's space, as a control's curve
//! shape (what the viewer draws for the control) or an input curve for spline IK.

use std::sync::Arc;

use glam::DMat4;
use sinew_core::{ComputeContext, ComputeError, Curve, Input, NodeSpec, NodeType, Output, SpecError};

/// `nurbsCurve`: the shape node holding a curve, after Maya's node of that name. `create`
/// (object space: set in the rig file, or connected from `curveFromPoints`) → `local`
/// (the same shared data, no copy) and `worldSpace` (its control points transformed by
/// the `worldMatrix` input; knots, degree and form unchanged, which is exact for a
/// non-rational B-spline under an affine map).
///
/// Departures from Maya: `worldMatrix` is an *input* here, as on `mesh` (connect the
/// parent transform's `worldMatrix`; unconnected, `worldSpace` equals `local`);
/// `worldSpace` is a single curve, not an array indexed by instance; Maya's `cached`
/// (the curve data a scene file writes) is what `create` holds. A control point that is
/// not finite is a compute error naming it.
pub struct NurbsCurveShape {
    spec: NodeSpec,
    create: Input<Arc<Curve>>,
    world_matrix: Input<DMat4>,
    world_space: Output<Arc<Curve>>,
    local: Output<Arc<Curve>>,
}

impl NurbsCurveShape {
    /// Creates the node type.
    pub fn new() -> Result<Self, SpecError> {
        let mut s = NodeSpec::builder("nurbsCurve");
        s.maya_names(&[
            ("create", "cr"),
            ("worldMatrix", "wm"),
            ("worldSpace", "ws"),
            ("local", "l"),
        ]);
        s.doc("a curve shape: create (object space) → local (shared) and worldSpace (transformed by worldMatrix)");
        let create = s.input("create", Arc::new(Curve::default()));
        let world_matrix = s.input("worldMatrix", DMat4::IDENTITY);
        // `local` is declared last: tools that show a node's final output (the viewer)
        // draw the object-space curve placed by the transform whose world matrix is
        // connected, which links the drawn shape to that control.
        let world_space = s.output("worldSpace", Arc::new(Curve::default()));
        let local = s.output("local", Arc::new(Curve::default()));
        s.attr_doc(create, "the curve in object space")
            .attr_doc(
                world_matrix,
                "object-to-world matrix: connect the parent transform's worldMatrix",
            )
            .attr_doc(world_space, "the curve in world space")
            .attr_doc(local, "create, checked and shared (object space)");
        s.affects(&[create.id()], &[local.id()]);
        s.affects(&[create.id(), world_matrix.id()], &[world_space.id()]);
        Ok(NurbsCurveShape {
            spec: s.build()?,
            create,
            world_matrix,
            world_space,
            local,
        })
    }
}

impl NodeType for NurbsCurveShape {
    fn spec(&self) -> &NodeSpec {
        &self.spec
    }

    fn compute(&self, ctx: &mut ComputeContext<'_>) -> Result<(), ComputeError> {
        let curve = ctx.get(self.create);
        if let Some(k) = curve.points.iter().position(|p| !p.is_finite()) {
            return Err(ComputeError::new(format!(
                "nurbsCurve.create: control point {k} is {} (not finite); give finite coordinates",
                curve.points[k]
            )));
        }
        if ctx.wants(self.local) {
            ctx.set(self.local, curve.clone());
        }
        if ctx.wants(self.world_space) {
            let m = ctx.get(self.world_matrix);
            if m == DMat4::IDENTITY {
                ctx.set(self.world_space, curve);
            } else {
                let world = Curve {
                    points: curve.points.iter().map(|&p| m.transform_point3(p)).collect(),
                    ..(*curve).clone()
                };
                ctx.set(self.world_space, Arc::new(world));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use sinew_core::{CompileOptions, Graph, Instance, Program, Value};

    fn graph() -> Graph {
        Graph::new(crate::registry().unwrap())
    }

    fn curve(v: Value) -> Arc<Curve> {
        match v {
            Value::Curve(c) => c,
            other => panic!("not a curve: {other}"),
        }
    }

    fn square() -> Curve {
        Curve {
            degree: 1,
            points: vec![
                DVec3::new(1.0, 0.0, 1.0),
                DVec3::new(1.0, 0.0, -1.0),
                DVec3::new(-1.0, 0.0, -1.0),
                DVec3::new(-1.0, 0.0, 1.0),
                DVec3::new(1.0, 0.0, 1.0),
            ],
            ..Curve::default()
        }
    }

    #[test]
    fn local_is_create_and_world_space_is_moved_by_the_world_matrix() {
        let mut g = graph();
        g.add_node("nurbsCurve", "shape").unwrap();
        g.set_path("shape.create", Value::Curve(Arc::new(square()))).unwrap();
        // Scale 2 then translate (0, 3, 0): (1, 0, 1) → (2, 3, 2), by hand.
        let m = DMat4::from_translation(DVec3::new(0.0, 3.0, 0.0)) * DMat4::from_scale(DVec3::splat(2.0));
        g.set_path("shape.worldMatrix", Value::Matrix(m)).unwrap();
        let local = curve(g.get_path("shape.local").unwrap());
        assert_eq!(*local, square());
        let world = curve(g.get_path("shape.worldSpace").unwrap());
        assert_eq!(world.points[0], DVec3::new(2.0, 3.0, 2.0));
        assert_eq!(world.points[2], DVec3::new(-2.0, 3.0, -2.0));
        assert_eq!((world.degree, &world.knots, world.form), (1, &local.knots, local.form));
        // Lazy and compiled evaluation agree bit for bit.
        let program = Arc::new(Program::compile(&g, &CompileOptions::default()).unwrap());
        let mut inst = Instance::new(program.clone());
        inst.evaluate(g.time()).unwrap();
        for p in ["shape.local", "shape.worldSpace"] {
            let lazy = g.get_path(p).unwrap();
            let compiled = inst.get(&program.handle(p).unwrap());
            assert!(lazy.same_bits(&compiled), "{p}: lazy {lazy} != compiled {compiled}");
        }
    }

    #[test]
    fn a_non_finite_point_is_an_error_naming_it() {
        let mut g = graph();
        g.add_node("nurbsCurve", "shape").unwrap();
        let mut c = square();
        c.points[3].y = f64::NAN;
        g.set_path("shape.create", Value::Curve(Arc::new(c))).unwrap();
        let e = g.get_path("shape.local").unwrap_err().to_string();
        assert!(e.contains("control point 3") && e.contains("not finite"), "{e}");
    }
}
