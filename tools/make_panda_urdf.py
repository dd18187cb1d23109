"""Writes models/panda_arm.urdf: Franka Panda arm kinematics, limits and published inertias.

Kinematics (joint origins and axes) are Franka's (as in pybullet_data/franka_panda/panda.urdf);
joint position limits are the robot's datasheet limits; velocity and effort limits are Franka's;
inertial parameters are the identified values of Gaz et al., "Dynamic Identification of the
Franka Emika Panda Robot With Retrieval of Feasible Parameters Using Penalty-Based Optimization",
IEEE RA-L 2019 (as shipped in franka_description). Meshes come from the pybullet wheel through
the package ``pybullet_data`` (registered at run time by gbh_drake.modeling.package_map).

Run:  python tools/make_panda_urdf.py   (the result is committed; a test checks it is current)
"""

from pathlib import Path

# name, parent, xyz, rpy, (lower, upper), velocity, effort
JOINTS = [
    ("panda_joint1", "panda_link0", (0, 0, 0.333), (0, 0, 0), (-2.8973, 2.8973), 2.1750, 87),
    ("panda_joint2", "panda_link1", (0, 0, 0), (-1.5707963267948966, 0, 0), (-1.7628, 1.7628),
     2.1750, 87),
    ("panda_joint3", "panda_link2", (0, -0.316, 0), (1.5707963267948966, 0, 0), (-2.8973, 2.8973),
     2.1750, 87),
    ("panda_joint4", "panda_link3", (0.0825, 0, 0), (1.5707963267948966, 0, 0), (-3.0718, -0.0698),
     2.1750, 87),
    ("panda_joint5", "panda_link4", (-0.0825, 0.384, 0), (-1.5707963267948966, 0, 0),
     (-2.8973, 2.8973), 2.6100, 12),
    ("panda_joint6", "panda_link5", (0, 0, 0), (1.5707963267948966, 0, 0), (-0.0175, 3.7525),
     2.6100, 12),
    ("panda_joint7", "panda_link6", (0.088, 0, 0), (1.5707963267948966, 0, 0), (-2.8973, 2.8973),
     2.6100, 12),
]

# link: mass, com xyz, (ixx, ixy, ixz, iyy, iyz, izz) about the com (Gaz et al. 2019).
INERTIA = {
    "panda_link0": (0.629769, (-0.041018, -0.00014, 0.049974),
                    (0.00315, 8.2904e-07, 0.00015, 0.00388, 8.2299e-06, 0.004285)),
    "panda_link1": (4.970684, (0.003875, 0.002081, -0.04762),
                    (0.70337, -0.000139, 0.006772, 0.70661, 0.019169, 0.009117)),
    "panda_link2": (0.646926, (-0.003141, -0.02872, 0.003495),
                    (0.007962, -0.003925, 0.010254, 0.02811, 0.000704, 0.025995)),
    "panda_link3": (3.228604, (0.027518, 0.039252, -0.066502),
                    (0.037242, -0.004761, -0.011396, 0.036155, -0.012805, 0.01083)),
    "panda_link4": (3.587895, (-0.05317, 0.104419, 0.027454),
                    (0.025853, 0.007796, -0.001332, 0.019552, 0.008641, 0.028323)),
    "panda_link5": (1.225946, (-0.011953, 0.041065, -0.038437),
                    (0.035549, -0.002117, -0.004037, 0.029474, 0.000229, 0.008627)),
    "panda_link6": (1.666555, (0.060149, -0.014117, -0.010517),
                    (0.001964, 0.000109, -0.001158, 0.004354, 0.000341, 0.005433)),
    "panda_link7": (0.735522, (0.010517, -0.004252, 0.061597),
                    (0.012516, -0.000428, -0.001196, 0.010027, -0.000741, 0.004815)),
}

PYBULLET = "package://pybullet_data/franka_panda/meshes"
#: pybullet's wheel has no visual mesh for link0 and link7, and their collision meshes name a
#: material file it does not ship; the multi-material visual meshes of link5, link6 and the hand
#: do not show in Meshcat; the visual meshes of links 1-4 are 1.1-1.3 MB of OBJ text each,
#: which made a run's replay 11 MB. models/franka/ keeps copies of the collision meshes (a few
#: hundred triangles each) without material lines, used as both visual and collision geometry.
OWN_COPIES = ("link0", "link1", "link2", "link3", "link4", "link5", "link6", "link7", "hand")


def copy_meshes(models_dir: Path) -> None:
    import pybullet_data

    src = Path(pybullet_data.getDataPath()) / "franka_panda" / "meshes" / "collision"
    (models_dir / "franka").mkdir(exist_ok=True)
    for name in (*OWN_COPIES, "finger"):  # (the finger: for the hook gripper's SDF)
        lines = (src / f"{name}.obj").read_text().splitlines()
        kept = [ln for ln in lines if not ln.startswith(("mtllib", "usemtl"))]
        header = "# Franka Emika Panda mesh from pybullet_data (Apache-2.0), material lines removed.\n"
        (models_dir / "franka" / f"{name}.obj").write_text(header + "\n".join(kept) + "\n")


def link_xml(name: str) -> str:
    mass, com, (ixx, ixy, ixz, iyy, iyz, izz) = INERTIA[name]
    idx = name[-1]
    own = f"link{idx}" in OWN_COPIES
    visual = f"package://gbh_drake/franka/link{idx}.obj" if own else f"{PYBULLET}/visual/link{idx}.obj"
    collision = (f"package://gbh_drake/franka/link{idx}.obj" if own
                 else f"{PYBULLET}/collision/link{idx}.obj")
    # Meshes with their own materials keep them; the copies get a colour.
    color = ("0.25 0.25 0.25 1" if idx == "7" else "0.95 0.95 0.95 1") if own else ""
    material = f'<material name="{name}_color"><color rgba="{color}"/></material>' if own else ""
    return f"""  <link name="{name}">
    <inertial>
      <origin xyz="{com[0]} {com[1]} {com[2]}" rpy="0 0 0"/>
      <mass value="{mass}"/>
      <inertia ixx="{ixx}" ixy="{ixy}" ixz="{ixz}" iyy="{iyy}" iyz="{iyz}" izz="{izz}"/>
    </inertial>
    <visual>
      <geometry><mesh filename="{visual}"/></geometry>
      {material}
    </visual>
    <collision>
      <geometry><mesh filename="{collision}"/></geometry>
    </collision>
  </link>
"""


def joint_xml(j) -> str:
    name, parent, xyz, rpy, (lo, hi), vel, eff = j
    child = "panda_link" + name[-1]
    return f"""  <joint name="{name}" type="revolute">
    <parent link="{parent}"/>
    <child link="{child}"/>
    <origin xyz="{xyz[0]} {xyz[1]} {xyz[2]}" rpy="{rpy[0]} {rpy[1]} {rpy[2]}"/>
    <axis xyz="0 0 1"/>
    <limit lower="{lo}" upper="{hi}" velocity="{vel}" effort="{eff}"/>
    <dynamics damping="0.0"/>
  </joint>
  <transmission name="{name}_tr">
    <type>transmission_interface/SimpleTransmission</type>
    <joint name="{name}">
      <hardwareInterface>hardware_interface/EffortJointInterface</hardwareInterface>
    </joint>
    <actuator name="{name}_motor"><mechanicalReduction>1</mechanicalReduction></actuator>
  </transmission>
"""


def make_urdf() -> str:
    parts = ['<?xml version="1.0"?>\n',
             "<!-- Generated by tools/make_panda_urdf.py; edit that script, not this file. -->\n",
             '<robot name="panda">\n']
    parts.append(link_xml("panda_link0"))
    for j in JOINTS:
        parts.append(link_xml("panda_link" + j[0][-1]))
        parts.append(joint_xml(j))
    parts.append("""  <link name="panda_link8"/>
  <joint name="panda_joint8" type="fixed">
    <parent link="panda_link7"/>
    <child link="panda_link8"/>
    <origin xyz="0 0 0.107" rpy="0 0 0"/>
  </joint>
</robot>
""")
    return "".join(parts)


if __name__ == "__main__":
    models = Path(__file__).resolve().parent.parent / "models"
    copy_meshes(models)
    out = models / "panda_arm.urdf"
    out.write_text(make_urdf())
    print(f"wrote {out}")
