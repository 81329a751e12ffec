from urdfgen import *
parts=[link("world")]
parts.append(link("base_x_link",0.01)); parts.append(joint("base_x_joint","world","base_x_link",kind="prismatic",axis=(1,0,0),lim=(-10,10),vel=1.0))
parts.append(link("base_y_link",0.01)); parts.append(joint("base_y_joint","base_x_link","base_y_link",kind="prismatic",axis=(0,1,0),lim=(-10,10),vel=1.0))
parts.append(link("base_link",116.0,[col(("box",(0.668,0.668,0.30)),(0,0,0.15))]))
parts.append(joint("base_yaw_joint","base_y_link","base_link",kind="continuous",axis=(0,0,1),vel=1.0))
parts.append(link("torso_lift_link",36.0,[col(("box",(0.35,0.45,0.55)),(-0.1,0,-0.05)),col(("box",(0.30,0.30,0.50)),(-0.1,0,-0.55))]))
parts.append(joint("torso_lift_joint","base_link","torso_lift_link",(-0.05,0,0.739675+0.1)))
parts.append(link("head_link",5.0,[col(("box",(0.2,0.3,0.2)),(0,0,0.1))]))
parts.append(joint("head_joint","torso_lift_link","head_link",(-0.05,0,0.25)))
arm=[
 ("l_shoulder_pan_joint","l_shoulder_pan_link",(0,0.188,0),(0,0,1),(-0.7146,2.2854),2.088,[col(("cyl",(0.1,0.35)),(0,0,-0.05))]),
 ("l_shoulder_lift_joint","l_shoulder_lift_link",(0.1,0,0),(0,1,0),(-0.5236,1.3963),2.082,[col(("sph",(0.1,)),(0,0,0))]),
 ("l_upper_arm_roll_joint","l_upper_arm_roll_link",(0,0,0),(1,0,0),(-0.8,3.9),3.27,[col(("cyl",(0.07,0.3)),(0.2,0,0),(0,PI/2,0))]),
 ("l_elbow_flex_joint","l_elbow_flex_link",(0.4,0,0),(0,1,0),(-2.3213,0.0),3.3,[col(("sph",(0.07,)),(0,0,0))]),
 ("l_forearm_roll_joint","l_forearm_roll_link",(0,0,0),(1,0,0),None,3.6,[col(("cyl",(0.055,0.24)),(0.16,0,0),(0,PI/2,0))]),
 ("l_wrist_flex_joint","l_wrist_flex_link",(0.321,0,0),(0,1,0),(-2.18,0.0),3.078,[col(("sph",(0.045,)),(0,0,0))]),
 ("l_wrist_roll_joint","l_wrist_roll_link",(0,0,0),(1,0,0),None,3.6,[col(("box",(0.1,0.1,0.06)),(0.07,0,0))]),
]
parent="torso_lift_link"
for (jn,ln,xyz,ax,lim,v,cols) in arm:
    parts.append(link(ln,2.0,cols))
    if lim is None:
        parts.append(joint(jn,parent,ln,xyz,kind="continuous",axis=ax,vel=v))
    else:
        parts.append(joint(jn,parent,ln,xyz,kind="revolute",axis=ax,lim=lim,vel=v))
    parent=ln
# Fingers: joint value = inner face to centre line (0 closed, 0.045 open); right mimics left.
parts.append(link("l_gripper_l_finger_link",0.1,[col(("box",(0.06,0.01,0.02)),(0.03,0.005,0))]))
parts.append(joint("l_gripper_finger_joint",parent,"l_gripper_l_finger_link",(0.13,0,0),kind="prismatic",axis=(0,1,0),lim=(0,0.045),vel=0.1,eff=100))
parts.append(link("l_gripper_r_finger_link",0.1,[col(("box",(0.06,0.01,0.02)),(0.03,-0.005,0))]))
parts.append(joint("l_gripper_r_finger_joint",parent,"l_gripper_r_finger_link",(0.13,0,0),kind="prismatic",axis=(0,1,0),lim=(-0.045,0),vel=0.1,eff=100,mimic=("l_gripper_finger_joint",-1)))
parts.append(link("l_gripper_tool_frame",0.001))
parts.append(joint("l_gripper_tool_joint",parent,"l_gripper_tool_frame",(0.18,0,0),(0,PI/2,0)))
open(__import__("os").path.join(__import__("os").path.dirname(__file__), "../../domains/robots/pr2_mobile.urdf"),"w").write(robot("pr2_mobile",
 "A PR2-like mobile manipulator (Tian et al., Section V-B): a planar base as prismatic x,\n     prismatic y and continuous yaw joints, a fixed torso (lift 0.1 m) and the left 7-DOF arm\n     with the published PR2 joint origins (shoulder offset 0.188 m, upper arm 0.4 m, forearm\n     0.321 m, tool frame 0.18 m past the wrist), axes and limits. Fingers on one prismatic\n     joint (0 to 0.045 m each side; the right finger mimics the left). The tool frame's z axis is the approach direction, as for the other robots.\n     Collision geometry: primitives sized to the links (approximate).", parts))
