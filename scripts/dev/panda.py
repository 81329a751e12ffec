from urdfgen import *
# Franka Emika Panda, published modified-DH parameters (a, d, alpha), Craig convention:
# joint origin = Tx(a_{i-1}) Rx(alpha_{i-1}) Tz(d_i)  ->  xyz (a, -sin(alpha) d, cos(alpha) d), rpy (alpha, 0, 0)
mdh=[(0,0.333,0),(0,0,-PI/2),(0,0.316,PI/2),(0.0825,0,PI/2),(-0.0825,0.384,-PI/2),(0,0,PI/2),(0.088,0,PI/2)]
lim=[(-2.8973,2.8973),(-1.7628,1.7628),(-2.8973,2.8973),(-3.0718,-0.0698),(-2.8973,2.8973),(-0.0175,3.7525),(-2.8973,2.8973)]
vel=[2.175,2.175,2.175,2.175,2.61,2.61,2.61]
eff=[87,87,87,87,12,12,12]
cols={
 "panda_link0":[col(("cyl",(0.08,0.14)),(-0.04,0,0.07))],
 "panda_link1":[col(("cyl",(0.065,0.2)),(0,0,-0.1))],
 "panda_link2":[col(("cyl",(0.065,0.2)),(0,-0.1,0),(PI/2,0,0))],
 "panda_link3":[col(("cyl",(0.06,0.16)),(0.04,0,-0.07))],
 "panda_link4":[col(("cyl",(0.06,0.16)),(-0.04,0.08,0),(PI/2,0,0))],
 "panda_link5":[col(("cyl",(0.06,0.22)),(0,0.04,-0.13))],
 "panda_link6":[col(("cyl",(0.055,0.12)),(0.045,0,0),(0,PI/2,0))],
 "panda_link7":[col(("cyl",(0.05,0.1)),(0,0,0.05))],
}
parts=[link("panda_link0",2.9,cols["panda_link0"])]
for i,((a,d,al),(lo,hi)) in enumerate(zip(mdh,lim)):
    parent=f"panda_link{i}"; child=f"panda_link{i+1}"
    parts.append(link(child,2.0,cols[child]))
    parts.append(joint(f"panda_joint{i+1}",parent,child,(a,-math.sin(al)*d,math.cos(al)*d),(al,0,0),"revolute",(0,0,1),(lo,hi),vel[i],eff[i]))
parts.append(link("panda_link8",0.01))
parts.append(joint("panda_joint8","panda_link7","panda_link8",(0,0,0.107)))
# Franka Hand: 0.2 m wide base (r_base = 0.1), fingers modelled open (0.04 m each side).
parts.append(link("panda_hand",0.73,[col(("box",(0.06,0.2,0.06)),(0,0,0.03))]))
parts.append(joint("panda_hand_joint","panda_link8","panda_hand",(0,0,0),(0,0,-PI/4)))
# Fingers: joint value = inner face to centre line (0 closed, 0.04 open); finger 2 mimics 1.
parts.append(link("panda_leftfinger",0.015,[col(("box",(0.02,0.012,0.045)),(0,0.006,0.0225))]))
parts.append(joint("panda_finger_joint1","panda_hand","panda_leftfinger",(0,0,0.0584),kind="prismatic",axis=(0,1,0),lim=(0,0.04),vel=0.2,eff=20))
parts.append(link("panda_rightfinger",0.015,[col(("box",(0.02,0.012,0.045)),(0,-0.006,0.0225))]))
parts.append(joint("panda_finger_joint2","panda_hand","panda_rightfinger",(0,0,0.0584),kind="prismatic",axis=(0,-1,0),lim=(0,0.04),vel=0.2,eff=20,mimic=("panda_finger_joint1",1)))
parts.append(link("panda_hand_tcp",0.001))
parts.append(joint("panda_hand_tcp_joint","panda_hand","panda_hand_tcp",(0,0,0.1034)))
open(__import__("os").path.join(__import__("os").path.dirname(__file__), "../../domains/robots/panda.urdf"),"w").write(robot("panda",
 "Franka Emika Panda with the Franka Hand. Kinematics: Franka's published modified-DH\n     parameters (d1 0.333, d3 0.316, a4 0.0825, a5 -0.0825, d5 0.384, a7 0.088, flange 0.107,\n     TCP 0.1034 m), joint position and velocity limits from the datasheet. Fingers on one\n     prismatic joint (0 to 0.04 m each side; finger 2 mimics finger 1). Collision geometry: primitives sized to\n     the links (approximate).", parts))
