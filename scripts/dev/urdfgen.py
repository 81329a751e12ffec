import math
PI=math.pi
def fmt(v): return " ".join(f"{x:.17g}" if abs(x - round(x, 9)) > 1e-12 else f"{round(x, 9):.10g}" for x in v)
def col(shape, xyz=(0,0,0), rpy=(0,0,0)):
    kind, dims = shape
    if kind=="box": g=f'<box size="{fmt(dims)}"/>'
    elif kind=="cyl": g=f'<cylinder radius="{dims[0]}" length="{dims[1]}"/>'
    else: g=f'<sphere radius="{dims[0]}"/>'
    return f'''    <collision>
      <origin xyz="{fmt(xyz)}" rpy="{fmt(rpy)}"/>
      <geometry>{g}</geometry>
    </collision>'''
def link(name, mass=None, cols=()):
    if mass is None:
        return f'  <link name="{name}"/>'
    return f'''  <link name="{name}">
    <inertial><mass value="{mass}"/><origin xyz="0 0 0"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
{chr(10).join(cols)}
  </link>'''.replace("\n\n","\n")
def joint(name, parent, child, xyz=(0,0,0), rpy=(0,0,0), kind="fixed", axis=(0,0,1), lim=None, vel=None, eff=100, mimic=None):
    s=f'''  <joint name="{name}" type="{kind}">
    <parent link="{parent}"/><child link="{child}"/>
    <origin xyz="{fmt(xyz)}" rpy="{fmt(rpy)}"/>'''
    if kind!="fixed":
        s+=f'\n    <axis xyz="{fmt(axis)}"/>'
        if kind=="continuous":
            s+=f'\n    <limit velocity="{vel}" effort="{eff}"/>'
        else:
            s+=f'\n    <limit lower="{fmt([lim[0]])}" upper="{fmt([lim[1]])}" velocity="{vel}" effort="{eff}"/>'
    if mimic:
        s+=f'\n    <mimic joint="{mimic[0]}" multiplier="{mimic[1]}" offset="0"/>'
    return s+"\n  </joint>"
def robot(name, comment, parts):
    return f'<?xml version="1.0"?>\n<!-- {comment} -->\n<robot name="{name}">\n' + "\n".join(parts) + "\n</robot>\n"
